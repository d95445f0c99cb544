//! Transparent huge pages for the hierarchy's arrays.
//!
//! On the 1M-triangle scenes a ray's walk is a chain of cache misses through some 50 MB of
//! nodes and triangle packets, and with 4 KB pages nearly every one is a TLB miss too (the
//! data TLB covers a few MB). On 2 MB pages the whole hierarchy fits in the second-level TLB.
//! Linux backs anonymous memory with huge pages only where the program asks when
//! `/sys/kernel/mm/transparent_hugepage/enabled` is `madvise` (a common default), by
//! `madvise(MADV_HUGEPAGE)`; Embree does so for its own hierarchy.
//!
//! [`huge_vec`] makes an empty `Vec` whose buffer is advised before it is written, so that the
//! first touch of each 2 MB-aligned stretch faults in a huge page; [`huge_copy`] fills one
//! with a copy of a slice. The buffer comes from the global allocator (no allocation of our
//! own, so no `unsafe` beyond the one call): it keeps 2 MB of spare capacity so that its end
//! is covered too (untouched, the spare costs address space only), and the part before its
//! first 2 MB boundary, under 2 MB, stays on small pages. Elsewhere than Linux with glibc, or
//! when the kernel refuses, the buffer is an ordinary one: the advice changes where the bytes
//! live, never what they are.
//!
//! Measured (`benches/README.md`, 1M triangles, one thread, against the same code on small
//! pages): incoherent rays 1.15–1.28× on the open sphere field and the teapot, coherent rays
//! and the closed field within noise (1.0–1.07×); `/proc/<pid>/smaps` shows the packets and
//! nodes as `AnonHugePages`.

/// Size of a huge page on x86-64 and of the alignment the advice needs.
const HUGE: usize = 2 << 20;

/// Arrays smaller than this stay on small pages (a huge page would be mostly empty).
const MIN_BYTES: usize = 2 * HUGE;

/// An empty `Vec` with room for `capacity` items whose buffer the kernel is asked to back with
/// transparent huge pages as it is written. Where the allocator hands back memory already
/// touched, only [`huge_copy`]'s collapse after the writing helps.
#[must_use]
pub(super) fn huge_vec<T>(capacity: usize) -> Vec<T> {
    let item = std::mem::size_of::<T>();
    if item == 0 || capacity.saturating_mul(item) < MIN_BYTES {
        return Vec::with_capacity(capacity);
    }
    let out = Vec::with_capacity(capacity + HUGE.div_ceil(item));
    let (first, last) = aligned_inside(&out);
    if last > first {
        advise(first, last - first, Advice::Fault);
    }
    out
}

/// A copy of `items` whose buffer the kernel is asked to back with transparent huge pages.
#[must_use]
pub(super) fn huge_copy<T: Copy>(items: &[T]) -> Vec<T> {
    let mut out = huge_vec(items.len());
    out.extend_from_slice(items);
    // A buffer the allocator recycled was faulted in on small pages before the advice: ask
    // for those to be collapsed into huge pages now (Linux 6.1 and later).
    let (first, _) = aligned_inside(&out);
    let filled = (out.as_ptr() as usize + std::mem::size_of_val(items)) / HUGE * HUGE;
    if std::mem::size_of_val(items) >= MIN_BYTES && filled > first {
        advise(first, filled - first, Advice::Collapse);
    }
    out
}

/// The 2 MB-aligned stretch inside the buffer of `v` (its whole capacity), as addresses.
fn aligned_inside<T>(v: &Vec<T>) -> (usize, usize) {
    let start = v.as_ptr() as usize;
    let end = start + v.capacity() * std::mem::size_of::<T>();
    (start.next_multiple_of(HUGE), end / HUGE * HUGE)
}

/// What to ask of the kernel.
#[derive(Clone, Copy)]
enum Advice {
    /// Back the range with huge pages when it is first touched (`MADV_HUGEPAGE`).
    Fault,
    /// Move the range's present small pages to huge pages now (`MADV_COLLAPSE`).
    Collapse,
}

/// Gives `advice` on `len` bytes from `addr`, both multiples of [`HUGE`], inside an allocation
/// this module owns; failure (an old kernel, THP disabled) is ignored.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn advise(addr: usize, len: usize, advice: Advice) {
    let advice = match advice {
        Advice::Fault => libc::MADV_HUGEPAGE,
        Advice::Collapse => libc::MADV_COLLAPSE,
    };
    // SAFETY: `MADV_HUGEPAGE` and `MADV_COLLAPSE` change no byte of memory and invalidate no
    // pointer: they only choose the size of the pages under the range (a collapse copies the
    // contents to the new page before remapping). The range lies inside the buffer of a
    // `Vec` that `huge_vec` has just allocated (or that `huge_copy` holds), 2 MB-aligned.
    #[allow(unsafe_code)]
    let _ = unsafe { libc::madvise(addr as *mut libc::c_void, len, advice) };
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn advise(_addr: usize, _len: usize, _advice: Advice) {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn copies_are_equal_whatever_their_size() {
        for n in [0usize, 1, 1000, MIN_BYTES / 4 + 17] {
            let v: Vec<u32> = (0..n as u32)
                .map(|i| i.wrapping_mul(2_654_435_761))
                .collect();
            assert_eq!(huge_copy(&v), v);
            let mut w = huge_vec(n);
            w.extend_from_slice(&v);
            assert_eq!(w, v);
        }
    }
}
