//! The identity of a shared value, for cache keys: the live refit's stages, and the
//! workbench's (the refit last sent, the drawing data kept between refits).
//!
//! The key holds the value: were it a bare address, a new log (or set of signals) allocated
//! where an old one was freed would pass for the old one, and a stage would be kept, a refit
//! skipped or a picture kept, that was made from other data.

use std::sync::Arc;

/// A shared value compared by identity: equal when both hold the same allocation.
pub struct Same<T>(Arc<T>);

impl<T> Same<T> {
    /// The identity of `value` (holding it while the key lives).
    pub fn of(value: &Arc<T>) -> Same<T> {
        Same(value.clone())
    }

    /// The value this key holds.
    pub fn value(&self) -> &T {
        &self.0
    }

    /// True when `value` is the value this key holds.
    pub fn is(&self, value: &Arc<T>) -> bool {
        Arc::ptr_eq(&self.0, value)
    }
}

impl<T> Clone for Same<T> {
    fn clone(&self) -> Self {
        Same(self.0.clone())
    }
}

impl<T> PartialEq for Same<T> {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

impl<T> std::fmt::Debug for Same<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Same({:p})", Arc::as_ptr(&self.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_values_in_two_allocations_are_not_the_same() {
        let a = Arc::new(vec![1.0, 2.0]);
        let b = Arc::new(vec![1.0, 2.0]);
        assert_eq!(Same::of(&a), Same::of(&a.clone()));
        assert_ne!(Same::of(&a), Same::of(&b));
        assert!(Same::of(&a).is(&a) && !Same::of(&a).is(&b));
    }

    #[test]
    fn a_key_keeps_its_value_alive_so_its_address_is_not_reused() {
        let a = Arc::new(vec![0u8; 64]);
        let key = Same::of(&a);
        drop(a);
        // The allocation the key names is still held: a new value cannot take its place.
        let b = Arc::new(vec![0u8; 64]);
        assert!(!key.is(&b));
    }
}
