//! The binary's allocator: mimalloc, asked for plain blocks wherever a plain
//! block is aligned enough.
//!
//! mimalloc places every block of 16 bytes or more on a 16-byte boundary
//! (its `MI_MAX_ALIGN_SIZE`, asserted for each block it hands out) and the
//! smaller ones on 8-byte boundaries. The `mimalloc` crate asks for every
//! block through `mi_malloc_aligned`, whose fast path holds only while the
//! size class's current page has a free block: when that page is used up,
//! it over-allocates size + alignment − 1 bytes from another size class
//! instead of starting a fresh page (62 such calls in one Jansen analysis,
//! about 150 instructions each against about 20 for the fast path). Plain
//! `mi_malloc` starts the fresh page. Larger alignments still take the
//! aligned calls.

use std::alloc::{GlobalAlloc, Layout};
use std::ffi::c_void;

use libmimalloc_sys as mi;

/// mimalloc, with plain calls where every block meets the alignment.
pub struct Allocator;

/// Whether every mimalloc block of `size` bytes is aligned to `align`.
fn plain(align: usize, size: usize) -> bool {
    align <= 8 || (align <= 16 && size >= 16)
}

// SAFETY: each call forwards to mimalloc, which returns a block of at least
// the requested size or null; plain calls only where `plain` holds, so the
// block meets the layout's alignment; `mi_free` releases blocks of either.
unsafe impl GlobalAlloc for Allocator {
    #[inline]
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if plain(layout.align(), layout.size()) {
            unsafe { mi::mi_malloc(layout.size()) as *mut u8 }
        } else {
            unsafe { mi::mi_malloc_aligned(layout.size(), layout.align()) as *mut u8 }
        }
    }

    #[inline]
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if plain(layout.align(), layout.size()) {
            unsafe { mi::mi_zalloc(layout.size()) as *mut u8 }
        } else {
            unsafe { mi::mi_zalloc_aligned(layout.size(), layout.align()) as *mut u8 }
        }
    }

    #[inline]
    unsafe fn dealloc(&self, ptr: *mut u8, _layout: Layout) {
        unsafe { mi::mi_free(ptr as *mut c_void) }
    }

    #[inline]
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if plain(layout.align(), new_size) {
            unsafe { mi::mi_realloc(ptr as *mut c_void, new_size) as *mut u8 }
        } else {
            unsafe { mi::mi_realloc_aligned(ptr as *mut c_void, new_size, layout.align()) as *mut u8 }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Blocks of every size class a solver run uses, at each alignment the
    /// plain calls take, are aligned; reallocation keeps contents.
    #[test]
    fn plain_blocks_meet_their_alignment() {
        let a = Allocator;
        for align in [1, 2, 4, 8, 16] {
            for size in (align..=4096).step_by(align) {
                let layout = Layout::from_size_align(size, align).expect("valid layout");
                // SAFETY: a non-zero size; each block is written within its size, then freed once.
                unsafe {
                    let p = a.alloc(layout);
                    assert!(!p.is_null() && (p as usize).is_multiple_of(align), "size {size} align {align}");
                    p.write(7);
                    let q = a.realloc(p, layout, size * 3);
                    assert!(
                        !q.is_null() && (q as usize).is_multiple_of(align) && q.read() == 7,
                        "realloc {size} align {align}"
                    );
                    a.dealloc(q, Layout::from_size_align(size * 3, align).expect("valid layout"));
                }
            }
        }
    }
}
