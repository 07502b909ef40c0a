//! What leaves driftlab for other hands: code and tables for the gyro's processor
//! (`firmware`) and the test report (`report`).

pub mod firmware;
pub mod report;
