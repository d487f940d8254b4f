//! Input checks, written to be cheap on a flight CPU: one pass, no early
//! exits inside the loops (the branch-free form compiles to a compare and
//! an `and` per value).

use crate::GPC_ROTATION_TOLERANCE;

/// Every value finite.
#[inline]
pub(crate) fn finite_all(values: &[f32]) -> bool {
    values.iter().fold(true, |ok, x| ok & x.is_finite())
}

/// `R` is a rotation: `RᵀR` within [`GPC_ROTATION_TOLERANCE`] of the identity
/// entry by entry, and `det R > 0` (a reflection is orthogonal too).
#[inline]
pub(crate) fn rotation_ok(r: &[[f32; 3]; 3]) -> bool {
    let col = |j: usize| [r[0][j], r[1][j], r[2][j]];
    let dot = |a: [f32; 3], b: [f32; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let c = [col(0), col(1), col(2)];
    let mut ok = true;
    for i in 0..3 {
        for j in i..3 {
            let want = if i == j { 1.0 } else { 0.0 };
            ok &= (dot(c[i], c[j]) - want).abs() <= GPC_ROTATION_TOLERANCE;
        }
    }
    let cross = [
        c[0][1] * c[1][2] - c[0][2] * c[1][1],
        c[0][2] * c[1][0] - c[0][0] * c[1][2],
        c[0][0] * c[1][1] - c[0][1] * c[1][0],
    ];
    ok & (dot(cross, c[2]) > 0.0)
}
