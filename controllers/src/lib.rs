//! The geometric PID controllers of Goodarzi, Lee & Lee, the flight-mode
//! scheduler and the gain checker. Not yet written: issue 4 builds it on the
//! `lie` crate. The crate exists now so the workspace has its final shape.
