//! The library behind the `parasils` command.
