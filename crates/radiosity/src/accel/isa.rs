//! Instruction-set dispatch for the ray queries: the same traversal code compiled twice, once
//! for the x86-64 baseline (SSE2) and once with AVX2, FMA, BMI1/2, LZCNT and POPCNT, and the
//! second chosen at run time when the processor has them.
//!
//! The traversal is written as lane loops (the eight slab tests of `node`, the four lanes
//! of `packet`); compiled for the baseline, LLVM turns each into two 4-wide SSE
//! operations, with AVX2 into one 8-wide one, and BMI gives the mask walks single
//! instructions. Results do not change: Rust never fuses a multiply and an add on its own
//! (no `-ffast-math`), so both builds execute the same IEEE operations in the same order and
//! return the same bits (`tests/bvh.rs` checks this on random scenes).
//!
//! | setting | default | meaning |
//! |---|---|---|
//! | [`Isa`] in effect | the best the processor has | [`set`] lowers it (benchmarks, tests) |
//!
//! Three of the crate's four `unsafe` blocks are here (the fourth is `madvise` in `pages`):
//! calling a `#[target_feature]` function needs the caller to promise that the processor has
//! the features, which [`std::is_x86_feature_detected`] establishes, and the intrinsics of
//! `prefetch` and `le_mask` are declared that way. Measured on the
//! 1M-triangle benchmark scenes (`benches/README.md`): with AVX2 1.03–1.3× the SSE2 build's
//! rays per second on every scene and query.

use std::sync::atomic::{AtomicU8, Ordering};

/// Instruction sets the queries are compiled for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, serde::Serialize)]
pub enum Isa {
    /// What every x86-64 (or any other) processor runs: SSE2.
    Baseline,
    /// x86-64 with AVX2, FMA, BMI1, BMI2, LZCNT and POPCNT (x86-64-v3).
    Avx2,
}

/// 0 = not chosen yet, else 1 + the `Isa` in effect.
static CHOICE: AtomicU8 = AtomicU8::new(0);

/// The best instruction set this processor runs.
#[must_use]
pub fn detected() -> Isa {
    #[cfg(target_arch = "x86_64")]
    {
        if std::is_x86_feature_detected!("avx2")
            && std::is_x86_feature_detected!("fma")
            && std::is_x86_feature_detected!("bmi1")
            && std::is_x86_feature_detected!("bmi2")
            && std::is_x86_feature_detected!("lzcnt")
            && std::is_x86_feature_detected!("popcnt")
        {
            return Isa::Avx2;
        }
    }
    Isa::Baseline
}

/// The instruction set the queries use now.
#[must_use]
pub fn current() -> Isa {
    match CHOICE.load(Ordering::Relaxed) {
        0 => {
            let isa = detected();
            CHOICE.store(1 + isa as u8, Ordering::Relaxed);
            isa
        }
        1 => Isa::Baseline,
        _ => Isa::Avx2,
    }
}

/// Makes the queries use `isa`, or the best the processor has if that is lower; returns the
/// one in effect. For benchmarks and tests: results are the same bits either way.
pub fn set(isa: Isa) -> Isa {
    let isa = isa.min(detected());
    CHOICE.store(1 + isa as u8, Ordering::Relaxed);
    isa
}

/// Runs `f` compiled for the instruction set in effect. `f` must be `#[inline(always)]` down
/// to its leaves for the choice to reach them; it is called once per query (or per batch).
#[inline(always)]
pub(super) fn run<R>(f: impl FnOnce() -> R) -> R {
    #[cfg(target_arch = "x86_64")]
    {
        if current() == Isa::Avx2 {
            // SAFETY: `current` is `Avx2` only when `detected` found every feature that
            // `avx2` enables.
            #[allow(unsafe_code)]
            return unsafe { avx2(f) };
        }
    }
    f()
}

/// `f()` compiled with the features of [`Isa::Avx2`] (closures given to it are inlined).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
fn avx2<R>(f: impl FnOnce() -> R) -> R {
    f()
}

/// The mask of the lanes r with `a[r] <= b[r]` (bit r), as `movmskps` makes it. (LLVM does
/// not find `movmskps` in the portable loop `m |= u32::from(a[r] <= b[r]) << r`: it spent
/// some 25 shuffles and scalar compares on it, the hottest spot of the packet traversal
/// under `perf`.)
#[inline(always)]
pub(super) fn le_mask(a: &[f32; 8], b: &[f32; 8]) -> u32 {
    #[cfg(target_arch = "x86_64")]
    {
        // SAFETY: `le_mask_sse` needs SSE, which belongs to every x86-64 processor.
        #[allow(unsafe_code)]
        unsafe {
            le_mask_sse(a, b)
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let mut m = 0;
        for r in 0..8 {
            m |= u32::from(a[r] <= b[r]) << r;
        }
        m
    }
}

/// [`le_mask`] in SSE: two compares, two `movmskps` (one 8-wide of each when inlined into
/// the AVX2 build).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "sse")]
#[inline]
fn le_mask_sse(a: &[f32; 8], b: &[f32; 8]) -> u32 {
    use std::arch::x86_64::{_mm_cmple_ps, _mm_movemask_ps, _mm_setr_ps};
    let half =
        |x: &[f32; 8], h: usize| _mm_setr_ps(x[4 * h], x[4 * h + 1], x[4 * h + 2], x[4 * h + 3]);
    let lo = _mm_movemask_ps(_mm_cmple_ps(half(a, 0), half(b, 0)));
    let hi = _mm_movemask_ps(_mm_cmple_ps(half(a, 1), half(b, 1)));
    (lo | hi << 4) as u32
}

/// Asks the cache for every 64-byte line that `x` spans, ahead of its use (a node's two; a
/// leaf's triangle packets, 144 bytes each, start mid-line and span three); no effect on any
/// result. (Measured on the 1M-triangle scenes, incoherent closest hits, 1 thread: 3–9 %
/// faster when a node's hit children are all prefetched before the nearest is entered.)
#[inline(always)]
pub(super) fn prefetch<T: ?Sized>(x: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let start = std::ptr::from_ref(x).cast::<i8>();
        let end = start as usize + std::mem::size_of_val(x);
        // From the line holding the first byte to the one holding the last.
        let mut line = start.wrapping_sub(start as usize & 63);
        while (line as usize) < end {
            // SAFETY: a prefetch is a hint that reads nothing the program can observe (the
            // address is never dereferenced), and the `sse` feature it is declared with
            // belongs to every x86-64 processor.
            #[allow(unsafe_code)]
            unsafe {
                _mm_prefetch::<_MM_HINT_T0>(line);
            }
            line = line.wrapping_add(64);
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = x;
}
