//! How a bake's memory goes back to the system: large blocks mapped on their own (set once by
//! the `bake` binary, [`return_large_blocks`]; the library leaves its users' allocator settings
//! alone), and freed heap pages handed back between stages ([`return_freed`]).
//!
//! Blocks below the allocator's mapping threshold (glibc: 128 KiB, fixed there by
//! [`return_large_blocks`]) live in its heap, and freeing them leaves their pages resident for
//! the heap to reuse. Allocations made after a large heap-resident structure is dropped, such as the patch tree
//! rebuilt when the solve's rows go, are larger blocks that are mapped on their own and do not
//! reuse those pages, so they are added on top unless the pages are returned first.

/// Return the heap's free pages to the system (glibc on Linux; elsewhere nothing to do). A
/// library user with another global allocator loses nothing: glibc's own heap is then trimmed.
pub(crate) fn return_freed() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: malloc_trim only releases free memory of the allocator; it is thread-safe.
    unsafe {
        libc::malloc_trim(0);
    }
}

/// Blocks of this many bytes and more are mapped on their own and returned to the system when
/// freed (glibc's default, fixed: left dynamic, glibc raises it as large blocks are freed, and
/// a bake's freed rows, trees and patch vectors then stay in its heap for good).
const MAP_ON_THEIR_OWN: i32 = 128 * 1024;

/// Keep large blocks out of the allocator's heap (glibc on Linux; elsewhere nothing to do), so
/// what one stage frees is returned rather than kept: on the 10⁵ floor the peak resident
/// memory falls by about 6 % and what is resident after the solve by half
/// (bench/results/floor-stages.md).
pub fn return_large_blocks() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only sets a parameter of the allocator; called before any thread starts.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, MAP_ON_THEIR_OWN);
    }
}
