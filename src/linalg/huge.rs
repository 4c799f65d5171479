//! Arrays that a time step streams, on transparent huge pages where the system allows it.
//!
//! A sweep of a large factor touches a new 4 KiB page every 512 values. Each is a miss of
//! the translation buffers (a few thousand entries: 8 MiB of 4 KiB pages) and, in a virtual
//! machine, a walk of two page tables. On 2 MiB pages the same arrays need a few hundred
//! entries, and the hardware's prefetchers run ahead across page boundaries undisturbed.
//! Measured on the development host (a virtual machine, two threads each reading 200 MB):
//! 19-26 GB/s on 4 KiB pages, 35-37 GB/s on 2 MiB pages.
//!
//! [`HugeBuf`] holds a fixed-length array. From [`HUGE_MIN_BYTES`] on, it is allocated
//! aligned to 2 MiB, its length rounded up to whole 2 MiB pages, and marked
//! `MADV_HUGEPAGE` before its first write (Linux, `transparent_hugepage` in `always` or
//! `madvise` mode), so that its pages are faulted in as huge pages. Where the system does
//! not allow it the advice is ignored and the array is an ordinary one; nothing depends on
//! it but speed.

use std::alloc::{alloc, dealloc, handle_alloc_error, Layout};
use std::ptr::NonNull;

/// The size of a huge page on x86-64 and of the alignment asked for, bytes.
const HUGE_PAGE: usize = 2 << 20;

/// Arrays from this size on go on huge pages (below, the rounding to a whole huge page
/// would waste more than it holds).
pub const HUGE_MIN_BYTES: usize = 1 << 20;

/// A fixed-length array of `T`, on transparent huge pages from [`HUGE_MIN_BYTES`] on (module
/// docs). It dereferences to `[T]`.
pub struct HugeBuf<T: Copy> {
    ptr: NonNull<T>,
    len: usize,
    /// The allocation's layout (size zero: nothing allocated).
    layout: Layout,
}

// SAFETY: `HugeBuf<T>` owns its `T`s as a `Vec<T>` does.
unsafe impl<T: Copy + Send> Send for HugeBuf<T> {}
// SAFETY: as above; shared access gives `&[T]` only.
unsafe impl<T: Copy + Sync> Sync for HugeBuf<T> {}

impl<T: Copy> HugeBuf<T> {
    /// A copy of `data`.
    pub fn from_slice(data: &[T]) -> Self {
        let len = data.len();
        let bytes = std::mem::size_of_val(data);
        if bytes == 0 {
            return Self::default();
        }
        let layout = if bytes >= HUGE_MIN_BYTES {
            Layout::from_size_align(bytes.div_ceil(HUGE_PAGE) * HUGE_PAGE, HUGE_PAGE)
        } else {
            Layout::array::<T>(len)
        }
        .expect("an array's layout within the address space");
        // SAFETY: the layout's size is not zero (`bytes > 0`).
        let raw = unsafe { alloc(layout) };
        let Some(ptr) = NonNull::new(raw.cast::<T>()) else {
            handle_alloc_error(layout)
        };
        if layout.align() == HUGE_PAGE {
            advise_huge(raw, layout.size());
        }
        // SAFETY: `ptr` holds room for `len` values of `T` (the layout is at least
        // `size_of::<T>() * len` bytes, aligned for `T`), and does not overlap `data`.
        unsafe { std::ptr::copy_nonoverlapping(data.as_ptr(), ptr.as_ptr(), len) };
        Self { ptr, len, layout }
    }

    /// True when the array was allocated for huge pages (whether the system gave them is
    /// its own affair).
    pub fn is_huge(&self) -> bool {
        self.layout.align() == HUGE_PAGE
    }
}

/// Marks `[p, p + bytes)` (aligned to a huge page, untouched) for transparent huge pages.
fn advise_huge(p: *mut u8, bytes: usize) {
    #[cfg(target_os = "linux")]
    // SAFETY: `madvise` with `MADV_HUGEPAGE` only sets a flag on the range's mappings (the
    // range is this process's own allocation); it changes no contents.
    unsafe {
        libc::madvise(p.cast(), bytes, libc::MADV_HUGEPAGE);
    }
    #[cfg(not(target_os = "linux"))]
    let _ = (p, bytes);
}

impl<T: Copy> Default for HugeBuf<T> {
    fn default() -> Self {
        Self {
            ptr: NonNull::dangling(),
            len: 0,
            layout: Layout::new::<()>(),
        }
    }
}

impl<T: Copy> Drop for HugeBuf<T> {
    fn drop(&mut self) {
        if self.layout.size() > 0 {
            // SAFETY: allocated by `alloc` with this layout in `from_slice`.
            unsafe { dealloc(self.ptr.as_ptr().cast(), self.layout) };
        }
    }
}

impl<T: Copy> std::ops::Deref for HugeBuf<T> {
    type Target = [T];
    fn deref(&self) -> &[T] {
        // SAFETY: `ptr` holds `len` initialized values (written in `from_slice`), or is
        // dangling and `len == 0`.
        unsafe { std::slice::from_raw_parts(self.ptr.as_ptr(), self.len) }
    }
}

impl<T: Copy> std::ops::DerefMut for HugeBuf<T> {
    fn deref_mut(&mut self) -> &mut [T] {
        // SAFETY: as in `deref`; `&mut self` makes the borrow unique.
        unsafe { std::slice::from_raw_parts_mut(self.ptr.as_ptr(), self.len) }
    }
}

impl<T: Copy> Clone for HugeBuf<T> {
    fn clone(&self) -> Self {
        Self::from_slice(self)
    }
}

impl<T: Copy> std::fmt::Debug for HugeBuf<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "HugeBuf(len {}, huge {})", self.len, self.is_huge())
    }
}

impl<T: Copy> From<Vec<T>> for HugeBuf<T> {
    fn from(v: Vec<T>) -> Self {
        Self::from_slice(&v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn holds_a_copy_of_its_slice_at_every_size() {
        for len in [
            0usize,
            1,
            7,
            1000,
            HUGE_MIN_BYTES / 8 - 1,
            HUGE_MIN_BYTES / 8,
            300_001,
        ] {
            let v: Vec<f64> = (0..len).map(|i| i as f64 * 0.5 - 3.0).collect();
            let mut b = HugeBuf::from_slice(&v);
            assert_eq!(&b[..], &v[..]);
            assert_eq!(b.is_huge(), len * 8 >= HUGE_MIN_BYTES, "len {len}");
            if len > 0 {
                assert_eq!(b.as_ptr() as usize % std::mem::align_of::<f64>(), 0);
                b[len - 1] = 42.0;
                let c = b.clone();
                assert_eq!(c[len - 1], 42.0);
                assert_eq!(&c[..len - 1], &v[..len - 1]);
            }
            if b.is_huge() {
                assert_eq!(b.as_ptr() as usize % HUGE_PAGE, 0);
            }
        }
        let r: HugeBuf<u32> = vec![3u32; HUGE_MIN_BYTES].into();
        assert!(r.is_huge() && r.iter().all(|&x| x == 3));
    }
}
