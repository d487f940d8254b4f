//! The C ABI as a static library, `libgeopid_control.a`, for C to link:
//! every `gpc_*` function of the library, and on a `no_std` target a panic
//! handler that parks the core (the laws have no panic that an input can
//! reach: bad inputs are status codes).
//!
//! Host: `cargo build -p geopid-control --release --example geopid_control` →
//! `target/release/examples/libgeopid_control.a`. A Cortex-M4F firmware:
//! the same with `--target thumbv7em-none-eabihf --no-default-features
//! --features libm`.

#![no_std]

pub use geopid_control::*;

#[cfg(not(feature = "std"))]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    loop {
        core::hint::spin_loop();
    }
}
