//! The CSV files the commands write, read as a header and rows: columns by
//! name, as numbers (`f64`) or as the text the file holds.
//!
//! The files are plain (no quoting: no cell holds a comma), so the reader
//! splits lines on commas; every row must have as many cells as the header.

// Each test binary uses its own part of this module.
#![allow(dead_code)]

use std::path::Path;

/// A CSV file: its header and its rows of cells.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Table {
    /// The table in `text`: a header line, then one line per row.
    pub fn parse(text: &str) -> Table {
        let mut lines = text.lines();
        let header: Vec<String> = lines
            .next()
            .expect("a header line")
            .split(',')
            .map(str::to_owned)
            .collect();
        let rows: Vec<Vec<String>> = lines
            .map(|line| line.split(',').map(str::to_owned).collect())
            .collect();
        for (k, row) in rows.iter().enumerate() {
            assert_eq!(
                row.len(),
                header.len(),
                "row {k} has {} cells, the header {}",
                row.len(),
                header.len()
            );
        }
        Table { header, rows }
    }

    /// The table in the file at `path`.
    pub fn read(path: &Path) -> Table {
        let text = std::fs::read_to_string(path)
            .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
        Table::parse(&text)
    }

    /// The column names, in order.
    pub fn header(&self) -> &[String] {
        &self.header
    }

    /// Whether a column is named `name`.
    pub fn has(&self, name: &str) -> bool {
        self.header.iter().any(|h| h == name)
    }

    /// The number of rows (the header excepted).
    pub fn rows(&self) -> usize {
        self.rows.len()
    }

    /// The index of column `name`.
    fn index(&self, name: &str) -> usize {
        self.header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name} in {:?}", self.header))
    }

    /// Column `name` as numbers.
    pub fn col(&self, name: &str) -> Vec<f64> {
        let i = self.index(name);
        self.rows
            .iter()
            .enumerate()
            .map(|(k, row)| {
                row[i]
                    .parse()
                    .unwrap_or_else(|e| panic!("row {k}, {name} = {:?}: {e}", row[i]))
            })
            .collect()
    }

    /// Column `name` as the file writes it.
    pub fn text(&self, name: &str) -> Vec<&str> {
        let i = self.index(name);
        self.rows.iter().map(|row| row[i].as_str()).collect()
    }

    /// Row `k`'s cells as the file writes them, in the header's order.
    pub fn cells(&self, k: usize) -> Vec<&str> {
        self.rows[k].iter().map(String::as_str).collect()
    }

    /// Row `k` as numbers, in the header's order.
    pub fn row(&self, k: usize) -> Vec<f64> {
        self.header.iter().map(|name| self.at(name, k)).collect()
    }

    /// Column `name` of row `k` as a number.
    pub fn at(&self, name: &str, k: usize) -> f64 {
        let cell = &self.rows[k][self.index(name)];
        cell.parse()
            .unwrap_or_else(|e| panic!("row {k}, {name} = {cell:?}: {e}"))
    }
}
