//! Wall-clock time for per-phase timings.
//!
//! `std::time::Instant` traps on wasm32-unknown-unknown, so the core never calls it there: the
//! binding crate injects a clock backed by `performance.now()`, and native code uses `Instant`.
//! Timings are reported only; they never influence results, which keeps runs deterministic.

/// A monotonic clock in milliseconds.
pub trait Clock: Send {
    fn now_ms(&self) -> f64;
}

/// `Instant`-based clock for native targets; a clock that always reads zero on wasm.
#[derive(Debug, Clone, Copy)]
pub struct DefaultClock {
    #[cfg(not(target_arch = "wasm32"))]
    origin: std::time::Instant,
}

// On wasm the struct has no field and Default could be derived; natively it cannot.
#[cfg_attr(target_arch = "wasm32", allow(clippy::derivable_impls))]
impl Default for DefaultClock {
    fn default() -> Self {
        DefaultClock {
            #[cfg(not(target_arch = "wasm32"))]
            origin: std::time::Instant::now(),
        }
    }
}

impl Clock for DefaultClock {
    fn now_ms(&self) -> f64 {
        #[cfg(not(target_arch = "wasm32"))]
        {
            self.origin.elapsed().as_secs_f64() * 1e3
        }
        #[cfg(target_arch = "wasm32")]
        {
            0.0
        }
    }
}
