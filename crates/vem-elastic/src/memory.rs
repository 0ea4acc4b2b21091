//! Returning freed memory to the operating system between the phases of a solve.

/// Hands the pages of memory the allocator holds freed back to the operating system (glibc's
/// `malloc_trim`; nothing elsewhere). Called between phases whose freed allocations the next
/// phase does not reuse: the mesh generation's and the insertion's work before the assembly,
/// the assembly's before a large factor. Without it glibc keeps them in its arenas (one per
/// thread) and the process' resident memory stays that much above what it uses, while the
/// next phase's large allocations are mapped afresh beside them.
pub fn release_free_memory() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: `malloc_trim` only releases free pages of the allocator's own arenas; it is
    // thread-safe (it locks each arena) and leaves every live allocation untouched.
    unsafe {
        libc::malloc_trim(0);
    }
}
