//! The workbench session file (in progress).
