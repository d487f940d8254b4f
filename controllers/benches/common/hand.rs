//! The paper's attitude and position laws written by hand on glam's own
//! types, for f32 and f64: the baseline the generic code is measured
//! against (`controllers/benches/update.rs`, and the closed-loop step in
//! `studies/benches/step.rs`, which includes this file). Same formulas,
//! branches and output as `controllers`, for the paper's gains and
//! quadrotor as constants.
#![allow(dead_code)]

/// The same laws by hand on glam (same formulas, branches and checks as
/// `controllers`, written for one type).
macro_rules! hand {
    ($m:ident, $s:ty, $v:ty, $mat:ty) => {
        pub mod $m {
            pub struct In {
                pub x: $v,
                pub v: $v,
                pub r: $mat,
                pub w: $v,
                pub ei: $v,
                pub eatt: $v,
                pub xd: [$v; 5],
                pub b1d: [$v; 3],
            }
            pub const M: $s = 0.755;
            pub const G: $s = 9.81;
            pub const J: [$s; 3] = [0.43e-2, 0.43e-2, 1.02e-2];
            const KX: $s = 12.8;
            const KV: $s = 4.22;
            const KI: $s = 1.28;
            const C1: $s = 3.6;
            pub const SIG: $s = 1.0;
            const KR: $s = 0.65;
            const KW: $s = 0.11;
            const KIA: $s = 0.06;
            const C2: $s = 0.8;

            fn jmul(v: $v) -> $v {
                <$v>::new(J[0] * v.x, J[1] * v.y, J[2] * v.z)
            }
            fn fin(v: $v) -> bool {
                v.is_finite()
            }

            /// (M, e_R, e_Ω, Ψ, ė_I) against R_d with Ω_d, Ω̇_d.
            #[inline]
            pub fn attitude(
                r: $mat,
                w: $v,
                eatt: $v,
                rd: $mat,
                wd: $v,
                wdd: $v,
            ) -> ($v, $v, $v, $s, $v) {
                let e = rd.transpose() * r;
                let er = 0.5
                    * <$v>::new(
                        e.y_axis.z - e.z_axis.y,
                        e.z_axis.x - e.x_axis.z,
                        e.x_axis.y - e.y_axis.x,
                    );
                // Ψ = ¼‖E − I‖², as the generic law computes it (never
                // negative, no cancellation near I), not ½(3 − tr E).
                let d = e - <$mat>::IDENTITY;
                let psi = 0.25
                    * (d.x_axis.dot(d.x_axis) + d.y_axis.dot(d.y_axis) + d.z_axis.dot(d.z_axis));
                let wb = e.transpose() * wd;
                let wdb = e.transpose() * wdd;
                let ew = w - wb;
                let m = -KR * er - KW * ew - KIA * eatt + wb.cross(jmul(wb)) + jmul(wdb);
                (m, er, ew, psi, ew + C2 * er)
            }

            /// What the generic law returns (read through `black_box`).
            #[allow(dead_code)]
            pub struct Out {
                pub f: $s,
                pub m: $v,
                pub rc: $mat,
                pub wc: $v,
                pub wcd: $v,
                pub ex: $v,
                pub ev: $v,
                pub er: $v,
                pub ew: $v,
                pub psi: $s,
                pub ei_rate: $v,
                pub eatt_rate: $v,
            }

            #[inline]
            pub fn position(i: &In) -> Option<Out> {
                if !fin(i.ei) {
                    return None;
                }
                let e3 = <$v>::Z;
                let ex = i.x - i.xd[0];
                let ev = i.v - i.xd[1];
                let sat = i.ei.clamp(<$v>::splat(-SIG), <$v>::splat(SIG));
                let slope = <$v>::new(
                    if i.ei.x.abs() <= SIG { 1.0 } else { 0.0 },
                    if i.ei.y.abs() <= SIG { 1.0 } else { 0.0 },
                    if i.ei.z.abs() <= SIG { 1.0 } else { 0.0 },
                );
                let ei_rate = ev + C1 * ex;
                let ki_sat = KI * sat;
                let a = -KX * ex - KV * ev - ki_sat - (M * G) * e3 + M * i.xd[2];
                let (rb1, rb2, re3) = (i.r.x_axis, i.r.y_axis, i.r.z_axis);
                let f = -a.dot(re3);
                let ksr = KI * slope * ei_rate;
                let acc = G * e3 - (f / M) * re3 + ki_sat / M;
                let ev_dot = acc - i.xd[2];
                let ad = -KX * ev - KV * ev_dot - ksr + M * i.xd[3];
                let re3d = i.w.y * rb1 - i.w.x * rb2;
                let fd = -ad.dot(re3) - a.dot(re3d);
                let jerk = -(fd * re3 + f * re3d) / M + ksr / M;
                let ev_ddot = jerk - i.xd[3];
                let eir_dot = ev_dot + C1 * ev;
                let add = -KX * ev_dot - KV * ev_ddot - KI * slope * eir_dot + M * i.xd[4];
                let (u, ud, udd) = (-a, -ad, -add);
                let n = u.length();
                let thrust_defined = n > <$s>::EPSILON.sqrt() * M * G;
                if !thrust_defined {
                    return None; // the fallback is not benchmarked
                }
                let inv = 1.0 / n;
                let b3 = u * inv;
                let q = b3.dot(ud);
                let b3d = (ud - q * b3) * inv;
                let b3dd = (udd - (2.0 * q) * b3d - (b3d.dot(ud) + b3.dot(udd)) * b3) * inv;
                let [b1d, b1dd, b1ddd] = i.b1d;
                // b2 = (u × b1d)/‖u × b1d‖ and 1/‖b3 × b1d‖ = ‖u‖/‖u × b1d‖:
                // the two square roots and reciprocals run side by side.
                let cu = u.cross(b1d);
                let ncu = cu.length();
                let heading_defined = ncu > <$s>::EPSILON.sqrt() * (1.0 + b1d.length()) * n;
                if !heading_defined {
                    return None;
                }
                let cd = b3d.cross(b1d) + b3.cross(b1dd);
                let cdd = b3dd.cross(b1d) + 2.0 * b3d.cross(b1dd) + b3.cross(b1ddd);
                let inv_cu = 1.0 / ncu;
                let b2 = cu * inv_cu;
                let invc = n * inv_cu;
                let qc = b2.dot(cd);
                let b1 = b2.cross(b3);
                let w1 = b3.dot(cd) * invc;
                let w3 = -b1.dot(cd) * invc;
                let w2 = b1.dot(b3d);
                let b3b2dd = (b3.dot(cdd) - 2.0 * qc * w1) * invc;
                let b1b2dd = (b1.dot(cdd) + 2.0 * qc * w3) * invc;
                let b1b3dd = (b1.dot(udd) - 2.0 * q * w2) * inv;
                let wc = <$v>::new(w1, w2, w3);
                let wcd = <$v>::new(b3b2dd - w2 * w3, b1b3dd - w3 * w1, -b1b2dd + w1 * w2);
                let rc = <$mat>::from_cols(b1, b2, b3);
                let (m, er, ew, psi, eatt_rate) = attitude(i.r, i.w, i.eatt, rc, wc, wcd);
                (f.is_finite() && fin(m)).then_some(Out {
                    f,
                    m,
                    rc,
                    wc,
                    wcd,
                    ex,
                    ev,
                    er,
                    ew,
                    psi,
                    ei_rate,
                    eatt_rate,
                })
            }
        }
    };
}

hand!(hand64, f64, glam::DVec3, glam::DMat3);
hand!(hand32, f32, glam::Vec3, glam::Mat3);
