//! Rest-to-rest motion profiles for PARA-SILSROB's axes.
#![no_std]
