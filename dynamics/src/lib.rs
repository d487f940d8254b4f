//! Rigid-body state on SE(3)×R⁶, the `Vehicle` trait and the paper's
//! quadrotor. Not yet written: issue 3 builds it on the `lie` crate. The
//! crate exists now so the workspace has its final shape.
