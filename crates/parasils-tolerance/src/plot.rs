//! The histogram of the tip deviations as a picture (feature `plot`).
