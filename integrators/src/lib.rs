//! The `Integrator` trait and the LGVI, RK4, RKMK4, Euler and Dormand–Prince
//! steppers. Not yet written: issue 3 builds it on `lie` and `dynamics`.
//! The crate exists now so the workspace has its final shape.
