//! Progress reporting from the library to whoever drives it (the CLI draws a bar on stderr).
//! The library only calls these hooks; it never prints.

/// Receives progress events. Implementations must be cheap and thread-safe.
pub trait Progress: Sync {
    /// A new stage starts with `total` units of work (0 when unknown).
    fn stage(&self, name: &str, total: u64);
    /// `n` more units of the current stage are done.
    fn advance(&self, n: u64);
    /// A warning the user should see (e.g. a scene without emitters).
    fn warn(&self, message: &str);
}

/// Ignores everything.
pub struct Silent;

impl Progress for Silent {
    fn stage(&self, _: &str, _: u64) {}
    fn advance(&self, _: u64) {}
    fn warn(&self, _: &str) {}
}
