//! The exact solution of the torque-free rigid body with a diagonal inertia,
//! in f64, as an independent reference for integrator tests.
//!
//! Angular velocity (Jacobi, for `I1 < I2 < I3` and `L² > 2E I2`, i.e. the
//! body tumbles about its major axis):
//! `Ω(t) = (A1 cn, s A2 sn, s A3 dn)(λt + τ0 | m)` with `s = sign Ω3(0)`,
//! `A1 = √((2EI3 − L²)/(I1(I3 − I1)))`, `A2 = √((2EI3 − L²)/(I2(I3 − I2)))`,
//! `A3 = √((L² − 2EI1)/(I3(I3 − I1)))`, `λ = √((I3 − I2)(L² − 2EI1)/(I1I2I3))`,
//! `m = (I2 − I1)(2EI3 − L²)/((I3 − I2)(L² − 2EI1))`.
//!
//! Attitude (Landau & Lifshitz §37): with the inertial `Z` axis along the
//! constant spatial momentum `π = RJΩ`, the Z-X-Z Euler angles of the body
//! are `θ = ∠(L, b3)`, `ψ = atan2(L1, L2)` from the body momentum `L = JΩ`,
//! and the precession obeys `φ̇ = |L| (I1Ω1² + I2Ω2²)/(I1²Ω1² + I2²Ω2²)`,
//! which is integrated here by composite 5-point Gauss–Legendre quadrature
//! (panels ≤ 0.01 s; the integrand is analytic, so the quadrature error is
//! far below 1e-14). `R(t) = C Rz(φ(t) − φ(0)) Rx(θ(t)) Rz(ψ(t))`, with `C`
//! fixed by `R(0)`.
//!
//! Jacobi functions by the AGM / descending Landen transformation
//! (Abramowitz & Stegun 16.4), the incomplete elliptic integral for the
//! phase `τ0` by Carlson's `R_F`.

use crate::DynamicsError;

type M = [[f64; 3]; 3];

/// The exact free rigid body; see the module docs for the formulas.
#[derive(Clone, Debug)]
pub struct ExactFreeBody {
    i: [f64; 3],
    amp: [f64; 3],
    sign: f64,
    lambda: f64,
    m: f64,
    tau0: f64,
    l_norm: f64,
    c: M,
}

impl ExactFreeBody {
    /// Inertia `diag(i)` with `i[0] < i[1] < i[2]`, initial angular velocity
    /// `omega0` and attitude `r0` (rows). Errors name the condition that fails:
    /// unordered inertia, or a motion about the minor axis (`L² < 2E I2`,
    /// relabel the axes) or on the separatrix (`L² = 2E I2`).
    pub fn new(i: [f64; 3], omega0: [f64; 3], r0: M) -> Result<Self, DynamicsError> {
        if !(0.0 < i[0] && i[0] < i[1] && i[1] < i[2]) || i.iter().any(|x| !x.is_finite()) {
            return Err(DynamicsError::InvalidParameter {
                field: "inertia",
                value: i[1],
                expected: "0 < I1 < I2 < I3 (value shown is I2)",
            });
        }
        if omega0.iter().any(|x| !x.is_finite()) {
            return Err(DynamicsError::NonFinite { field: "omega0" });
        }
        let e2: f64 = (0..3).map(|k| i[k] * omega0[k] * omega0[k]).sum();
        let l2: f64 = (0..3).map(|k| (i[k] * omega0[k]).powi(2)).sum();
        let margin = l2 - e2 * i[1];
        if margin <= 1e-12 * l2 {
            return Err(DynamicsError::InvalidParameter {
                field: "omega0",
                value: margin,
                expected: "L² − 2E·I2 > 0 (rotation about the major axis; value shown is L² − 2E·I2)",
            });
        }
        let a1 = ((e2 * i[2] - l2) / (i[0] * (i[2] - i[0]))).max(0.0).sqrt();
        let a2 = ((e2 * i[2] - l2) / (i[1] * (i[2] - i[1]))).max(0.0).sqrt();
        let a3 = ((l2 - e2 * i[0]) / (i[2] * (i[2] - i[0]))).sqrt();
        let lambda = ((i[2] - i[1]) * (l2 - e2 * i[0]) / (i[0] * i[1] * i[2])).sqrt();
        let m = (i[1] - i[0]) * (e2 * i[2] - l2) / ((i[2] - i[1]) * (l2 - e2 * i[0]));
        let sign = if omega0[2] < 0.0 { -1.0 } else { 1.0 };
        let s = if a2 > 0.0 {
            (sign * omega0[1] / a2).clamp(-1.0, 1.0)
        } else {
            0.0
        };
        let f = incomplete_f(s.asin(), m);
        let tau0 = if omega0[0] >= 0.0 {
            f
        } else {
            2.0 * complete_k(m) - f
        };
        let mut me = Self {
            i,
            amp: [a1, a2, a3],
            sign,
            lambda,
            m,
            tau0,
            l_norm: l2.sqrt(),
            c: IDENTITY,
        };
        let (theta, psi) = me.nutation_spin(me.omega(0.0));
        // C = R0 Rz(ψ0)ᵀ Rx(θ0)ᵀ, so that R(0) = C Rx(θ0) Rz(ψ0) = R0.
        me.c = mul(mul(r0, transpose(rz(psi))), transpose(rx(theta)));
        Ok(me)
    }

    /// Exact angular velocity at `t`, body frame.
    pub fn omega(&self, t: f64) -> [f64; 3] {
        let (sn, cn, dn) = jacobi(self.lambda * t + self.tau0, self.m);
        [
            self.amp[0] * cn,
            self.sign * self.amp[1] * sn,
            self.sign * self.amp[2] * dn,
        ]
    }

    /// Exact attitude at `t` (rows).
    pub fn attitude(&self, t: f64) -> M {
        let (theta, psi) = self.nutation_spin(self.omega(t));
        let phi = self.precession(t);
        mul(mul(mul(self.c, rz(phi)), rx(theta)), rz(psi))
    }

    /// Energy `½ΩᵀJΩ` (constant).
    pub fn energy(&self) -> f64 {
        let w = self.omega(0.0);
        0.5 * (0..3).map(|k| self.i[k] * w[k] * w[k]).sum::<f64>()
    }

    fn nutation_spin(&self, w: [f64; 3]) -> (f64, f64) {
        let l = [self.i[0] * w[0], self.i[1] * w[1], self.i[2] * w[2]];
        let theta = (l[0].hypot(l[1])).atan2(l[2]);
        let psi = l[0].atan2(l[1]);
        (theta, psi)
    }

    fn phi_dot(&self, t: f64) -> f64 {
        let w = self.omega(t);
        let (i1, i2) = (self.i[0], self.i[1]);
        self.l_norm * (i1 * w[0] * w[0] + i2 * w[1] * w[1])
            / (i1 * i1 * w[0] * w[0] + i2 * i2 * w[1] * w[1])
    }

    /// `φ(t) − φ(0)` by composite Gauss–Legendre quadrature.
    fn precession(&self, t: f64) -> f64 {
        const X: [f64; 5] = [
            0.0,
            -0.538_469_310_105_683_1,
            0.538_469_310_105_683_1,
            -0.906_179_845_938_664,
            0.906_179_845_938_664,
        ];
        const W: [f64; 5] = [
            0.568_888_888_888_888_9,
            0.478_628_670_499_366_5,
            0.478_628_670_499_366_5,
            0.236_926_885_056_189_1,
            0.236_926_885_056_189_1,
        ];
        // φ̇ oscillates at the rate λ of the elliptic argument: panels of
        // 0.01 s suit |Ω| ~ 1 rad/s, but at |Ω| = 100 rad/s 5-point Gauss
        // over a panel spanning λh ≈ 1 rad left 5e-5 in R after 2 s
        // (found by `cargo xtask stress`, against two integrators that
        // agreed to 7e-12). Panels span at most 0.1 rad of the argument.
        let width = 0.01f64.min(0.1 / self.lambda.abs().max(1e-300));
        let panels = ((t.abs() / width).ceil() as usize).max(1);
        let h = t / panels as f64;
        // Neumaier-compensated sum: thousands of panels would otherwise add
        // ~√n ε |φ| of rounding noise, which central differences of R
        // amplify by 1/h.
        let (mut sum, mut comp) = (0.0f64, 0.0f64);
        for p in 0..panels {
            let mid = (p as f64 + 0.5) * h;
            let panel: f64 = (0..5)
                .map(|k| W[k] * self.phi_dot(mid + 0.5 * h * X[k]))
                .sum();
            let t = sum + panel;
            comp += if sum.abs() >= panel.abs() {
                (sum - t) + panel
            } else {
                (panel - t) + sum
            };
            sum = t;
        }
        (sum + comp) * 0.5 * h
    }
}

const IDENTITY: M = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

fn rz(a: f64) -> M {
    let (s, c) = a.sin_cos();
    [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
}

fn rx(a: f64) -> M {
    let (s, c) = a.sin_cos();
    [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]
}

fn mul(a: M, b: M) -> M {
    let mut c = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            c[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    c
}

fn transpose(a: M) -> M {
    let mut c = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            c[i][j] = a[j][i];
        }
    }
    c
}

/// Jacobi elliptic functions `(sn, cn, dn)(u | m)` for `0 ≤ m < 1`, by the
/// arithmetic-geometric mean (A&S 16.4).
pub fn jacobi(u: f64, m: f64) -> (f64, f64, f64) {
    if m < 1e-12 {
        let (s, c) = u.sin_cos();
        return (s, c, 1.0);
    }
    let mut a = [0.0f64; 16];
    let mut c = [0.0f64; 16];
    a[0] = 1.0;
    let mut b = (1.0 - m).sqrt();
    c[0] = m.sqrt();
    let mut twon = 1.0;
    let mut n = 0;
    while (c[n] / a[n]).abs() > f64::EPSILON && n < 15 {
        let an = a[n];
        n += 1;
        c[n] = 0.5 * (an - b);
        let t = (an * b).sqrt();
        a[n] = 0.5 * (an + b);
        b = t;
        twon *= 2.0;
    }
    let mut phi = twon * a[n] * u;
    while n > 0 {
        let t = c[n] * phi.sin() / a[n];
        phi = 0.5 * (t.asin() + phi);
        n -= 1;
    }
    let sn = phi.sin();
    let cn = phi.cos();
    // dn > 0 for m < 1, and `1 − m sn²` has no cancellation unless m → 1
    // (relative error ~ ε/(1 − m)); the quotient cn/cos(φ − φ_prev) of the
    // Landen recursion loses digits wherever cn ≈ 0 (measured: 22 ulp).
    let dn = (1.0 - m * sn * sn).sqrt();
    (sn, cn, dn)
}

/// Carlson's symmetric integral `R_F(x, y, z)` (duplication to 1e-3, then
/// the fifth-order series; truncation error ~ 1e-18).
fn carlson_rf(mut x: f64, mut y: f64, mut z: f64) -> f64 {
    for _ in 0..60 {
        let a = (x + y + z) / 3.0;
        let (dx, dy, dz) = (1.0 - x / a, 1.0 - y / a, 1.0 - z / a);
        if dx.abs().max(dy.abs()).max(dz.abs()) < 1e-3 {
            let e2 = dx * dy - dz * dz;
            let e3 = dx * dy * dz;
            return (1.0 - e2 / 10.0 + e3 / 14.0 + e2 * e2 / 24.0 - 3.0 * e2 * e3 / 44.0)
                / a.sqrt();
        }
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lam = sx * sy + sx * sz + sy * sz;
        x = 0.25 * (x + lam);
        y = 0.25 * (y + lam);
        z = 0.25 * (z + lam);
    }
    f64::NAN
}

/// Incomplete elliptic integral of the first kind `F(φ | m)`, |φ| ≤ π/2.
pub fn incomplete_f(phi: f64, m: f64) -> f64 {
    let (s, c) = phi.sin_cos();
    s * carlson_rf(c * c, 1.0 - m * s * s, 1.0)
}

/// Complete elliptic integral `K(m)`.
pub fn complete_k(m: f64) -> f64 {
    carlson_rf(0.0, 1.0 - m, 1.0)
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)] // index notation mirrors the formulas
mod tests {
    use super::*;

    // K(1/2) = Γ(1/4)²/(4√π) = 1.854074677301372 (A&S table 17.1).
    #[test]
    fn complete_k_matches_gamma_closed_form() {
        assert!((complete_k(0.5) - 1.854_074_677_301_372).abs() < 1e-15);
    }

    /// Values from mpmath's `ellipfun` at 30 digits, m = 1/3; 4e-15 is a few
    /// ulp at these magnitudes.
    #[test]
    fn jacobi_matches_mpmath() {
        let table = [
            (
                -7.0,
                [
                    -0.064_273_345_187_664_12,
                    0.997_932_330_921_484_6,
                    0.999_311_252_329_721_2,
                ],
            ),
            (
                0.5,
                [
                    0.473_637_640_369_355_9,
                    0.880_719_811_078_045_8,
                    0.961_884_848_552_630_1,
                ],
            ),
            (
                3.3,
                [
                    0.166_789_565_822_980_75,
                    -0.985_992_515_556_067_3,
                    0.995_352_741_616_857,
                ],
            ),
            (
                10.0,
                [
                    0.389_397_044_115_332,
                    -0.921_069_998_444_332_2,
                    0.974_400_660_583_082_4,
                ],
            ),
        ];
        for (u, want) in table {
            let (s, c, d) = jacobi(u, 1.0 / 3.0);
            for (got, want) in [s, c, d].into_iter().zip(want) {
                assert!((got - want).abs() < 4e-15, "u={u}: {got} vs {want}");
            }
        }
    }

    #[test]
    fn jacobi_identities_and_derivatives() {
        let m = 1.0 / 3.0;
        let k = complete_k(m);
        let (sn, cn, _) = jacobi(k, m);
        assert!(
            (sn - 1.0).abs() < 1e-14 && cn.abs() < 1e-7,
            "sn(K)={sn} cn(K)={cn}"
        );
        for j in 0..200 {
            let u = -7.0 + 0.07 * j as f64;
            let (s, c, d) = jacobi(u, m);
            // A few ulp of 1: each side is a sum of rounded squares.
            assert!((s * s + c * c - 1.0).abs() < 4e-15);
            assert!(
                (d * d + m * s * s - 1.0).abs() < 4e-15,
                "dn id u={u} {}",
                d * d + m * s * s - 1.0
            );
            let h = 1e-5;
            let (sp, cp, dp) = jacobi(u + h, m);
            let (sm, cm, dm) = jacobi(u - h, m);
            assert!(
                ((sp - sm) / (2.0 * h) - c * d).abs() < 1e-9,
                "u={u} {}",
                (sp - sm) / (2.0 * h) - c * d
            );
            assert!(
                ((cp - cm) / (2.0 * h) + s * d).abs() < 1e-9,
                "cn u={u} {}",
                (cp - cm) / (2.0 * h) + s * d
            );
            assert!(
                ((dp - dm) / (2.0 * h) + m * s * c).abs() < 1e-9,
                "dn u={u} {}",
                (dp - dm) / (2.0 * h) + m * s * c
            );
            // F inverts sn on the first quarter period.
            if u > 0.0 && u < k - 0.1 {
                assert!((incomplete_f(s.asin(), m) - u).abs() < 1e-13);
            }
        }
    }

    /// The reference itself: Euler's equations (by central differences of
    /// the exact Ω), `ṘRᵀ`-consistency `RᵀṘ = Ω^`, conservation of `RJΩ`,
    /// and `R ∈ SO(3)`, along 20 s.
    #[test]
    fn exact_solution_satisfies_the_equations() {
        let i = [1.0, 2.0, 3.0];
        let r0 = mul(rz(0.3), rx(-0.7));
        for w0 in [[1.0, 0.0, 1.0], [0.4, -0.8, -1.1], [-1.0, 0.3, 0.9]] {
            let b = ExactFreeBody::new(i, w0, r0).unwrap();
            let w = b.omega(0.0);
            for k in 0..3 {
                assert!((w[k] - w0[k]).abs() < 1e-14, "Ω(0) {w:?} vs {w0:?}");
            }
            let r = b.attitude(0.0);
            for a in 0..3 {
                for c in 0..3 {
                    assert!((r[a][c] - r0[a][c]).abs() < 1e-14);
                }
            }
            let pi0 = spatial(&i, r, w);
            let h = 1e-5;
            for j in 1..=40 {
                let t = 0.5 * j as f64;
                let (w, wp, wm) = (b.omega(t), b.omega(t + h), b.omega(t - h));
                let wd: Vec<f64> = (0..3).map(|k| (wp[k] - wm[k]) / (2.0 * h)).collect();
                let euler = [
                    (i[1] - i[2]) / i[0] * w[1] * w[2],
                    (i[2] - i[0]) / i[1] * w[2] * w[0],
                    (i[0] - i[1]) / i[2] * w[0] * w[1],
                ];
                for k in 0..3 {
                    assert!((wd[k] - euler[k]).abs() < 1e-8, "Euler eq at t={t}");
                }
                let (r, rp, rm) = (b.attitude(t), b.attitude(t + h), b.attitude(t - h));
                let mut rd = [[0.0; 3]; 3];
                for a in 0..3 {
                    for c in 0..3 {
                        rd[a][c] = (rp[a][c] - rm[a][c]) / (2.0 * h);
                    }
                }
                let om = mul(transpose(r), rd);
                let vee = [om[2][1], om[0][2], om[1][0]];
                for k in 0..3 {
                    assert!(
                        (vee[k] - w[k]).abs() < 1e-8,
                        "RᵀṘ vs Ω at t={t}: {vee:?} {w:?}"
                    );
                }
                let rtr = mul(transpose(r), r);
                for a in 0..3 {
                    for c in 0..3 {
                        let id = if a == c { 1.0 } else { 0.0 };
                        assert!((rtr[a][c] - id).abs() < 1e-14);
                    }
                }
                let pi = spatial(&i, r, w);
                for k in 0..3 {
                    assert!((pi[k] - pi0[k]).abs() < 1e-13, "π drift at t={t}");
                }
            }
        }
    }

    fn spatial(i: &[f64; 3], r: M, w: [f64; 3]) -> [f64; 3] {
        let l = [i[0] * w[0], i[1] * w[1], i[2] * w[2]];
        [0, 1, 2].map(|a| (0..3).map(|k| r[a][k] * l[k]).sum())
    }

    #[test]
    fn minor_axis_motion_is_a_named_error() {
        let e = ExactFreeBody::new([1.0, 2.0, 3.0], [1.0, 0.0, 0.1], IDENTITY).unwrap_err();
        assert!(e.to_string().contains("omega0"), "{e}");
    }
}
