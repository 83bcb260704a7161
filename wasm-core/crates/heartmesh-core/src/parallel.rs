//! Native data parallelism for the loops whose elements are independent (smoothing sweeps, spline
//! evaluation at the vertices, closest points of the attractors).
//!
//! Why it cannot change a result: every helper here hands each worker a contiguous range of the
//! output and the worker computes each element with the same operations a single thread would
//! (no reduction is split across threads). So any thread count, and wasm32 (always one thread,
//! no rayon compiled in), give the same bits.
//!
//! Why a pool (rayon) and not `std::thread::scope`: the loop runs ~250 iterations of a few
//! hundred microseconds each, plus 200 smoothing sweeps of ~60 us per remesh; spawning threads
//! for each would cost as much as the work. The pool's workers stay warm between calls.
//!
//! The thread count is process-wide, fixed when the pool is first used: the one a front end set
//! ([`set_threads`]), else the `HEARTMESH_THREADS` environment variable ([`threads_from_env`]),
//! else one. Why one by default: on our 2-vCPU CI-class VM, quiet (load average ~1, SurFCo,
//! medians of 7, two interleaved batches), two threads were SLOWER than one: total 391 / 430 ms
//! against 364 / 362 ms, closest points 57 against 49 ms, evaluation 26 against 20 ms. The
//! parallel parts are tens to hundreds of microseconds and the workers fall asleep during the
//! single-threaded solve between them; waking a virtual CPU costs about what a part saves. On
//! a loaded machine a descheduled worker holds up the join (load ~6: wall 4.8-6.1 s against
//! 4.6-4.8 s at one thread). Asking for threads is for machines where that has been measured to
//! pay.

use std::sync::atomic::{AtomicUsize, Ordering};

/// More threads than this do not pay at the method's mesh sizes (a few thousand vertices, a few
/// hundred attractors): the work per sweep is tens of microseconds.
pub const MAX_THREADS: usize = 4;

/// Environment variable the front ends read to force a thread count (1 = no threads).
pub const THREADS_ENV: &str = "HEARTMESH_THREADS";

/// 0 = not set: one thread unless the environment asks for more.
static REQUESTED: AtomicUsize = AtomicUsize::new(0);

/// Asks for `n` worker threads (0 = the default). Call before the first reconstruction: the pool is
/// built once, on first use, and keeps its size.
pub fn set_threads(n: usize) {
    REQUESTED.store(n, Ordering::Relaxed);
}

/// The thread count asked for in [`THREADS_ENV`], if it is a whole number.
pub fn threads_from_env() -> Option<usize> {
    std::env::var(THREADS_ENV).ok()?.trim().parse().ok()
}

/// Reads [`THREADS_ENV`] and passes it to [`set_threads`] (front ends call this once at start).
pub fn configure_from_env() {
    if let Some(n) = threads_from_env() {
        set_threads(n);
    }
}

#[cfg(not(target_arch = "wasm32"))]
mod imp {
    use super::{MAX_THREADS, REQUESTED};
    use std::sync::atomic::Ordering;
    use std::sync::OnceLock;

    /// None: one thread (asked for, or the pool could not be built).
    static POOL: OnceLock<Option<rayon::ThreadPool>> = OnceLock::new();

    fn pool() -> Option<&'static rayon::ThreadPool> {
        POOL.get_or_init(|| {
            let requested = match REQUESTED.load(Ordering::Relaxed) {
                0 => super::threads_from_env().unwrap_or(0),
                n => n,
            };
            // 0 (nothing asked for): one thread, see the module docs.
            let n = requested.min(4 * MAX_THREADS);
            if n < 2 {
                return None;
            }
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .thread_name(|i| format!("heartmesh-{i}"))
                .build()
                .ok()
        })
        .as_ref()
    }

    pub fn threads() -> usize {
        pool().map_or(1, |p| p.current_num_threads())
    }

    /// Runs `f` on the pool (so that the chunked calls inside it are cheap joins between warm
    /// workers), or on this thread when there is no pool.
    pub fn install<R: Send>(f: impl FnOnce() -> R + Send) -> R {
        match pool() {
            // Already on a worker (nested use): run here.
            Some(p) if p.current_thread_index().is_none() => p.install(f),
            _ => f(),
        }
    }

    pub fn map_parts<R: Send>(
        ranges: Vec<std::ops::Range<usize>>,
        f: &(impl Fn(std::ops::Range<usize>) -> R + Sync),
    ) -> Vec<R> {
        use rayon::prelude::*;
        match pool() {
            Some(p) => p.install(|| ranges.into_par_iter().map(f).collect()),
            None => ranges.into_iter().map(f).collect(),
        }
    }

    pub fn for_each_chunk<T: Send, U: Send>(
        a: &mut [T],
        b: &mut [U],
        parts: usize,
        f: &(impl Fn(usize, &mut [T], &mut [U]) + Sync),
    ) {
        let n = a.len();
        let len = n.div_ceil(parts);
        let Some(p) = pool() else {
            return f(0, a, b);
        };
        p.install(|| {
            rayon::scope(|s| {
                let mut rest_a = a;
                let mut rest_b = b;
                let mut start = 0;
                while rest_a.len() > len {
                    let (ha, ta) = rest_a.split_at_mut(len);
                    let (hb, tb) = rest_b.split_at_mut(len.min(rest_b.len()));
                    let s0 = start;
                    s.spawn(move |_| f(s0, ha, hb));
                    rest_a = ta;
                    rest_b = tb;
                    start += len;
                }
                // The last part runs on this worker.
                f(start, rest_a, rest_b);
            })
        });
    }
}

#[cfg(target_arch = "wasm32")]
mod imp {
    pub fn threads() -> usize {
        1
    }

    pub fn install<R: Send>(f: impl FnOnce() -> R + Send) -> R {
        f()
    }

    pub fn map_parts<R: Send>(
        ranges: Vec<std::ops::Range<usize>>,
        f: &(impl Fn(std::ops::Range<usize>) -> R + Sync),
    ) -> Vec<R> {
        ranges.into_iter().map(f).collect()
    }

    pub fn for_each_chunk<T: Send, U: Send>(
        a: &mut [T],
        b: &mut [U],
        _parts: usize,
        f: &(impl Fn(usize, &mut [T], &mut [U]) + Sync),
    ) {
        f(0, a, b)
    }
}

/// Worker threads in use (1 in wasm, or when one was asked for).
pub fn threads() -> usize {
    imp::threads()
}

/// Runs `f` where the chunked helpers are cheapest: on a pool worker natively, so that a loop of
/// many short parallel sweeps (the smoothing) does not pay a cross-thread wake-up per sweep.
pub fn install<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    imp::install(f)
}

/// How many parts `items` elements are worth splitting into when one element costs about
/// `cost` units (~ns): at most [`threads`], and each part at least [`MIN_PART_COST`].
pub fn parts_for(items: usize, cost: usize) -> usize {
    let t = threads();
    if t < 2 {
        return 1;
    }
    let total = items.saturating_mul(cost.max(1));
    (total / MIN_PART_COST).clamp(1, t)
}

/// Work (in the units of [`parts_for`]'s `cost`, ~ns) below which a part is not worth a thread:
/// measured, handing a part to a warm worker and joining it costs a few microseconds.
pub const MIN_PART_COST: usize = 20_000;

/// Calls `f(start, a_part, b_part)` on `parts` contiguous parts of `a` (and the parts of `b` at
/// the same indices; `b` may be shorter, its parts are then truncated), in parallel natively.
/// `start` is the index of the part's first element. With `parts <= 1`, or one thread, it is one
/// call on the whole slices.
pub fn for_each_chunk<T: Send, U: Send>(
    a: &mut [T],
    b: &mut [U],
    parts: usize,
    f: impl Fn(usize, &mut [T], &mut [U]) + Sync,
) {
    if parts <= 1 || a.len() < 2 {
        return f(0, a, b);
    }
    imp::for_each_chunk(a, b, parts.min(a.len()), &f)
}

/// `f` of each of `parts` contiguous ranges covering `0..n` (the parts of [`for_each_chunk`]), in
/// parallel natively; the results come back in range order, so a caller that combines them in
/// that order gets what one pass would.
pub fn map_parts<R: Send>(
    n: usize,
    parts: usize,
    f: impl Fn(std::ops::Range<usize>) -> R + Sync,
) -> Vec<R> {
    let len = n.div_ceil(parts.clamp(1, n.max(1))).max(1);
    let ranges: Vec<_> = (0..n.div_ceil(len).max(1))
        .map(|k| k * len..((k + 1) * len).min(n))
        .collect();
    if ranges.len() == 1 {
        return ranges.into_iter().map(f).collect();
    }
    imp::map_parts(ranges, &f)
}

/// [`for_each_chunk`] over one slice.
pub fn for_each_chunk1<T: Send>(a: &mut [T], parts: usize, f: impl Fn(usize, &mut [T]) + Sync) {
    let mut none: [(); 0] = [];
    for_each_chunk(a, &mut none, parts, |s, a, _| f(s, a));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_cover_every_element_once_in_order() {
        for n in [0usize, 1, 2, 3, 7, 100, 1001] {
            for parts in [1usize, 2, 3, 4, 8] {
                let mut a: Vec<usize> = vec![usize::MAX; n];
                let mut b: Vec<usize> = vec![0; n];
                for_each_chunk(&mut a, &mut b, parts, |start, pa, pb| {
                    assert_eq!(pa.len(), pb.len());
                    for (i, (x, y)) in pa.iter_mut().zip(pb.iter_mut()).enumerate() {
                        *x = start + i;
                        *y += 1;
                    }
                });
                assert!(
                    a.iter().enumerate().all(|(i, &x)| x == i),
                    "n {n} parts {parts}"
                );
                assert!(b.iter().all(|&y| y == 1));
            }
        }
    }

    #[test]
    fn shorter_second_slice_and_nesting() {
        let mut a = vec![0u32; 50];
        let mut b = vec![0u32; 10];
        for_each_chunk(&mut a, &mut b, 4, |start, pa, pb| {
            assert!(pb.len() <= pa.len());
            pa.fill(start as u32 + 1);
            pb.fill(1);
        });
        assert!(a.iter().all(|&x| x > 0));
        assert!(b.iter().all(|&x| x == 1));
        let total = install(|| {
            let mut c = vec![1u64; 1000];
            for_each_chunk1(&mut c, 4, |start, part| {
                for (i, x) in part.iter_mut().enumerate() {
                    *x = (start + i) as u64;
                }
            });
            c.iter().sum::<u64>()
        });
        assert_eq!(total, 999 * 1000 / 2);
    }

    #[test]
    fn map_parts_returns_ranges_in_order() {
        for n in [0usize, 1, 5, 100, 1001] {
            for parts in [0usize, 1, 2, 3, 4, 9] {
                let got = map_parts(n, parts, |r| r);
                assert!(got.len() <= parts.max(1), "n {n} parts {parts}: {got:?}");
                let mut next = 0;
                for r in &got {
                    assert_eq!(r.start, next);
                    next = r.end;
                }
                assert_eq!(next, n);
            }
        }
    }

    #[test]
    fn parts_grow_with_work_up_to_the_threads() {
        assert_eq!(parts_for(0, 100), 1);
        assert_eq!(parts_for(10, 100), 1);
        let p = parts_for(1_000_000, 1000);
        assert!(p >= 1 && p <= threads().max(1));
        assert_eq!(p, threads());
    }
}
