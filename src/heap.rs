//! Handing freed heap pages back to the system between stages.
//!
//! Blocks below the allocator's mapping threshold (glibc: 128 KiB, which the `bake` binary fixes
//! there) live in its heap, and freeing them leaves their pages resident for the heap to reuse.
//! Allocations made after a large heap-resident structure is dropped, such as the patch tree
//! rebuilt when the solve's rows go, are larger blocks that are mapped on their own and do not
//! reuse those pages, so they are added on top unless the pages are returned first.

/// Return the heap's free pages to the system (glibc on Linux; elsewhere nothing to do). A
/// library user with another global allocator loses nothing: glibc's own heap is then trimmed.
pub fn return_freed() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: malloc_trim only releases free memory of the allocator; it is thread-safe.
    unsafe {
        libc::malloc_trim(0);
    }
}
