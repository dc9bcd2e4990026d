//! Fixture loading and error statistics for the validation tests.
