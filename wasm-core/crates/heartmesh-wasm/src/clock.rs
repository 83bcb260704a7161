//! A `performance.now()` clock for the core's per-phase timings.
//!
//! `std::time::Instant` traps on wasm32-unknown-unknown, so the session injects this clock into every
//! reconstruction. `performance` exists in browsers, in workers and in Node >= 16; where it is
//! missing, `Date.now()` (millisecond resolution) is the fallback. Timings never affect results.

use heartmesh_core::clock::Clock;
use wasm_bindgen::prelude::*;

#[wasm_bindgen]
extern "C" {
    #[wasm_bindgen(js_namespace = performance, js_name = now)]
    fn performance_now() -> f64;
}

/// Milliseconds from `performance.now()` (or `Date.now()` when there is no `performance`).
#[derive(Debug, Clone, Copy)]
pub struct PerformanceClock {
    has_performance: bool,
}

impl PerformanceClock {
    pub fn new() -> Self {
        let global = js_sys::global();
        let has_performance = js_sys::Reflect::get(&global, &JsValue::from_str("performance"))
            .map(|p| p.is_object())
            .unwrap_or(false);
        PerformanceClock { has_performance }
    }
}

impl Default for PerformanceClock {
    fn default() -> Self {
        Self::new()
    }
}

impl Clock for PerformanceClock {
    fn now_ms(&self) -> f64 {
        if self.has_performance {
            performance_now()
        } else {
            js_sys::Date::now()
        }
    }
}
