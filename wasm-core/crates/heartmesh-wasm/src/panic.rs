//! Panic reporting across the wasm boundary.
//!
//! A Rust panic in wasm32 aborts with an `unreachable` trap, and JavaScript only sees
//! "RuntimeError: unreachable". The hook keeps the panic message (and prints it with
//! `console.error`) so the worker can report what happened before it is discarded: after a trap the
//! module's state is not trustworthy, so the worker treats it as fatal and the client recreates it.

use std::sync::Mutex;
use wasm_bindgen::prelude::*;

static LAST_PANIC: Mutex<Option<String>> = Mutex::new(None);

#[wasm_bindgen]
extern "C" {
    #[wasm_bindgen(js_namespace = console, js_name = error)]
    fn console_error(message: &str);
}

/// Installs the hook once; called from the module's start function.
pub fn install() {
    std::panic::set_hook(Box::new(|info| {
        let message = format!("heartmesh core panicked: {info}");
        console_error(&message);
        // A poisoned lock still holds a usable value; the hook must never panic itself.
        let mut slot = LAST_PANIC.lock().unwrap_or_else(|e| e.into_inner());
        *slot = Some(message);
    }));
}

/// The message of the last panic, if any (cleared by reading it).
#[wasm_bindgen]
pub fn take_panic_message() -> Option<String> {
    let mut slot = LAST_PANIC.lock().unwrap_or_else(|e| e.into_inner());
    slot.take()
}
