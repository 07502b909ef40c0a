//! The chamber simulator (in progress).
