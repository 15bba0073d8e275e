//! The last line of the wall around third-party parsers (the `gltf`, `image`, `exr` and DDS
//! decoders): a panic inside one becomes one error naming what was being read, never an abort of
//! the whole command. Inputs are checked before the parsers see them (`gltf_check`, the readers'
//! own size checks), so this only catches what those checks missed; and it cannot catch an
//! allocation failure, which aborts: sizes are checked before anything is allocated from them.
//!
//! The default panic hook would still print the panic's message and location to stderr before the
//! error is returned; a hook installed once forwards to the previous one except on a thread inside
//! `contained`, so the user sees the one error, not a backtrace hint as well.

use std::cell::Cell;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Once;

thread_local! {
    /// How many `contained` calls are running on this thread (they may nest).
    static INSIDE: Cell<u32> = const { Cell::new(0) };
}

/// Installs the quieting hook once, around whatever hook is in place.
fn install() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if INSIDE.with(Cell::get) == 0 {
                previous(info);
            }
        }));
    });
}

/// Runs `parse`; a panic inside it is returned as the error "the `what` reader failed: MESSAGE".
pub fn contained<T>(what: &str, parse: impl FnOnce() -> Result<T, String>) -> Result<T, String> {
    install();
    INSIDE.with(|c| c.set(c.get() + 1));
    let got = catch_unwind(AssertUnwindSafe(parse));
    INSIDE.with(|c| c.set(c.get() - 1));
    got.unwrap_or_else(|payload| {
        let message = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a panic with no message".into());
        Err(format!("the {what} reader failed on this file ({message}); please report it with the file"))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_inside_is_one_error_and_nesting_is_counted() {
        let e = contained::<()>("test", || panic!("index 7 out of range")).unwrap_err();
        assert!(e.contains("the test reader failed") && e.contains("index 7 out of range"), "{e}");
        let inner = contained("outer", || contained::<u8>("inner", || Err("no".into())));
        assert_eq!(inner, Err("no".to_string()));
        assert_eq!(INSIDE.with(Cell::get), 0);
    }
}
