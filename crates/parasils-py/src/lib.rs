//! Python bindings of parasils.
