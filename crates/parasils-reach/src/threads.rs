//! The map's work spread over threads, with results independent of the
//! thread count.

use core::sync::atomic::{AtomicUsize, Ordering};

use crate::check::Checker;
use crate::map::ReachOptions;

/// The threads to use for `options`.
pub(super) fn threads(options: &ReachOptions) -> usize {
    if options.threads > 0 {
        options.threads
    } else {
        std::thread::available_parallelism().map_or(1, usize::from)
    }
}

/// Runs `work(i, &mut checker)` for `i` in `0..n` on `threads` threads, each
/// item with a fresh copy of `base` (so that a result does not depend on
/// which thread computed it), and returns the results in order.
pub(super) fn parallel_map<R: Send>(
    n: usize,
    threads: usize,
    base: &Checker,
    work: impl Fn(usize, &mut Checker) -> R + Sync,
) -> Vec<R> {
    parallel_map_items(n, threads, |i| work(i, &mut base.clone()))
}

/// Runs `work(i)` for `i` in `0..n` on `threads` threads and returns the
/// results in order.
pub(super) fn parallel_map_items<R: Send>(
    n: usize,
    threads: usize,
    work: impl Fn(usize) -> R + Sync,
) -> Vec<R> {
    let next = AtomicUsize::new(0);
    let mut parts: Vec<Vec<(usize, R)>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads.clamp(1, n.max(1)))
            .map(|_| {
                s.spawn(|| {
                    let mut out = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        if i >= n {
                            break out;
                        }
                        out.push((i, work(i)));
                    }
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
            .collect()
    });
    // Each result to its item's place (no sort: the items are 0..n).
    let mut slots: Vec<Option<R>> = core::iter::repeat_with(|| None).take(n).collect();
    for (i, r) in parts.drain(..).flatten() {
        if let Some(slot) = slots.get_mut(i) {
            *slot = Some(r);
        }
    }
    slots.into_iter().flatten().collect()
}
