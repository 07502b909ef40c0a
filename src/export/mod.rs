//! What leaves driftlab for other hands: code and tables for the gyro's processor
//! (`firmware`), parameter files for flight controllers (`flight`) and the test report
//! (`report`).

pub mod firmware;
pub mod flight;
pub mod report;
