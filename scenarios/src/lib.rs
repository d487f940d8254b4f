//! Scenes, the simulation loop, metrics and MCAP/CSV output. Not yet
//! written: issue 5 builds it on every other crate. The crate exists now so
//! the workspace has its final shape.
