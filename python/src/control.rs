//! The paper's position and attitude laws over N states at once, for
//! people who keep their own simulator. glam f64 underneath: the fastest
//! of the four (backend, scalar) pairs in the controller benches at f64.

use controllers::{
    AccelerationModel, AttitudeGains, AttitudeReference, PositionGains, PositionInput,
    PositionReference, RigidBodyParams, VehicleState, attitude_control as rs_attitude,
    position_control as rs_position,
};
use lie::{GlamF64, M3, Rotation, So3Mat, V3, ops};
use numpy::PyReadonlyArrayDyn;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;
use scenes::scene::{AccelModel, GainsSpec};

use crate::arrays::{Col, array, input_col};

type B = GlamF64;

#[inline]
fn v3(a: &Col, i: usize) -> V3<B> {
    let e = a.row(i);
    B::vec3(e[0], e[1], e[2])
}

#[inline]
fn m3(a: &Col, i: usize) -> M3<B> {
    let e = a.row(i);
    ops::from_elems::<B>([[e[0], e[1], e[2]], [e[3], e[4], e[5]], [e[6], e[7], e[8]]])
}

#[inline]
fn push3(to: &mut Vec<f64>, v: V3<B>) {
    to.extend_from_slice(&B::vec3_to_array(v));
}

/// The gains from a JSON object with the scene file's `[gains]` keys (any
/// left out: the paper's); an unknown key or a bad value is a
/// `ValueError` naming it.
fn gains(json: Option<&str>) -> PyResult<GainsSpec> {
    let g: GainsSpec = match json {
        None => GainsSpec::default(),
        Some(text) => {
            serde_json::from_str(text).map_err(|e| PyValueError::new_err(format!("gains: {e}")))?
        }
    };
    for (name, v) in [
        ("k_x", g.k_x),
        ("k_v", g.k_v),
        ("k_i", g.k_i),
        ("k_r", g.k_r),
        ("k_omega", g.k_omega),
        ("k_att_i", g.k_att_i),
        ("c1", g.c1),
        ("c2", g.c2),
        ("sigma", g.sigma),
    ] {
        if !v.is_finite() {
            return Err(PyValueError::new_err(format!(
                "gains.{name} = {v}: must be finite"
            )));
        }
    }
    Ok(g)
}

fn params(mass: f64, inertia: [f64; 3], gravity: f64) -> PyResult<RigidBodyParams<B>> {
    let positive = |name: &str, v: f64| {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(PyValueError::new_err(format!(
                "{name} = {v}: must be finite and > 0"
            )))
        }
    };
    Ok(RigidBodyParams {
        mass: positive("mass", mass)?,
        inertia: ops::diag::<B>(
            positive("inertia[0]", inertia[0])?,
            positive("inertia[1]", inertia[1])?,
            positive("inertia[2]", inertia[2])?,
        ),
        gravity: if gravity.is_finite() {
            gravity
        } else {
            return Err(PyValueError::new_err(format!(
                "gravity = {gravity}: must be finite"
            )));
        },
    })
}

/// A controller's complaint about row `i`, as `ValueError` with `field`
/// and `row`.
fn control_error(py: Python<'_>, i: usize, e: controllers::ControlError) -> PyErr {
    let err = PyValueError::new_err(format!("row {i}: {e}"));
    let field = match e {
        controllers::ControlError::NonFinite { field }
        | controllers::ControlError::NonFiniteReference { field } => Some(field),
        _ => None,
    };
    let v = err.value(py);
    // Attributes are extras beside the message; failing to set one keeps
    // the error itself.
    let _ = v.setattr("row", i);
    let _ = v.setattr("field", field);
    err
}

/// Checks that `d` has only keys from `names`.
fn known_keys(what: &str, d: Option<&Bound<'_, PyDict>>, names: &[&str]) -> PyResult<()> {
    for k in d.iter().flat_map(|d| d.keys()) {
        let k: String = k.extract()?;
        if !names.contains(&k.as_str()) {
            return Err(PyValueError::new_err(format!(
                "{what}: unknown key `{k}`: expected {}",
                names.join(", ")
            )));
        }
    }
    Ok(())
}

/// Array `name` of `d`, shape `(n, *tail)` or `tail` (broadcast); `n`
/// from the array when `None`. Absent: `None`.
fn column(
    what: &str,
    d: Option<&Bound<'_, PyDict>>,
    name: &str,
    n: Option<usize>,
    tail: &[usize],
) -> PyResult<Option<(usize, Col)>> {
    let Some(a) = d.map(|d| d.get_item(name)).transpose()?.flatten() else {
        return Ok(None);
    };
    let a: PyReadonlyArrayDyn<'_, f64> = a
        .extract()
        .map_err(|e| PyValueError::new_err(format!("{what}.{name}: not a float array ({e})")))?;
    input_col(&format!("{what}.{name}"), &a, n, tail, n.is_some(), false).map(Some)
}

/// A required column.
fn required(
    what: &str,
    d: &Bound<'_, PyDict>,
    name: &str,
    n: Option<usize>,
    tail: &[usize],
) -> PyResult<(usize, Col)> {
    column(what, Some(d), name, n, tail)?
        .ok_or_else(|| PyValueError::new_err(format!("{what}: `{name}` is missing")))
}

/// An optional column, `default` (one row) repeated when absent.
fn optional(
    what: &str,
    d: Option<&Bound<'_, PyDict>>,
    name: &str,
    n: usize,
    default: [f64; 3],
) -> PyResult<Col> {
    Ok(match column(what, d, name, Some(n), &[3])? {
        Some((_, v)) => v,
        None => Col::one(&default),
    })
}

/// `mass`, `inertia` (diagonal) and `gravity` from `params` (the paper's
/// for those left out).
fn params_of(d: Option<&Bound<'_, PyDict>>) -> PyResult<RigidBodyParams<B>> {
    known_keys("params", d, &["mass", "inertia", "gravity"])?;
    let get = |name: &str| d.map(|d| d.get_item(name)).transpose().map(Option::flatten);
    let mass = get("mass")?
        .map(|v| v.extract())
        .transpose()?
        .unwrap_or(dynamics::paper::MASS);
    let inertia: [f64; 3] = get("inertia")?
        .map(|v| v.extract())
        .transpose()?
        .unwrap_or(dynamics::paper::INERTIA);
    let gravity = get("gravity")?
        .map(|v| v.extract())
        .transpose()?
        .unwrap_or(dynamics::paper::GRAVITY);
    params(mass, inertia, gravity)
}

/// What the position law returns, in order, and each one's values per
/// state.
const POSITION_OUTPUTS: [&str; 12] = [
    "thrust",
    "moment",
    "Rc",
    "omega_c",
    "omega_c_dot",
    "e_x",
    "e_v",
    "e_R",
    "e_omega",
    "psi",
    "e_i_pos_rate",
    "e_i_att_rate",
];
const POSITION_WIDTHS: [usize; 12] = [1, 3, 9, 3, 3, 3, 3, 3, 3, 1, 3, 3];

/// Which of `names` to return: all without a selection; an unknown name
/// is a `ValueError` listing the known ones.
fn selected<const K: usize>(
    outputs: Option<Vec<String>>,
    names: &[&str; K],
) -> PyResult<[bool; K]> {
    let Some(list) = outputs else {
        return Ok([true; K]);
    };
    let mut want = [false; K];
    for o in list {
        let k = names.iter().position(|n| *n == o).ok_or_else(|| {
            PyValueError::new_err(format!(
                "outputs: unknown `{o}`: expected {}",
                names.join(", ")
            ))
        })?;
        want[k] = true;
    }
    Ok(want)
}

fn flat9(m: M3<B>) -> [f64; 9] {
    let e = ops::elems::<B>(m);
    [
        e[0][0], e[0][1], e[0][2], e[1][0], e[1][1], e[1][2], e[2][0], e[2][1], e[2][2],
    ]
}

/// Rows below this many run on the calling thread (a pool's hand-off
/// costs more than the law for them).
const PARALLEL_ROWS: usize = 4096;

/// A row's control error: its index and the law's complaint.
type RowError = (usize, controllers::ControlError);

/// Output columns of `widths[k]` values a row for `n` rows (empty where
/// not `want`ed), filled by `block(rows, slices)` over contiguous blocks
/// of rows on rayon's pool (one block below `PARALLEL_ROWS` rows), each
/// block writing its rows' part of every column in place; a failing
/// row's error, if any (with several, any one of them).
fn in_blocks<F>(
    n: usize,
    widths: &[usize],
    want: &[bool],
    block: F,
) -> Result<Vec<Vec<f64>>, RowError>
where
    F: Fn(std::ops::Range<usize>, &mut [&mut [f64]]) -> Result<(), RowError> + Sync,
{
    let mut cols: Vec<Vec<f64>> = widths
        .iter()
        .zip(want)
        .map(|(w, on)| vec![0.0; if *on { w * n } else { 0 }])
        .collect();
    let blocks = if n < PARALLEL_ROWS {
        1
    } else {
        4 * rayon::current_num_threads()
    };
    let size = n.div_ceil(blocks).max(1);
    // Block b's slice of every column: rows b·size.. of it.
    let mut parts: Vec<(std::ops::Range<usize>, Vec<&mut [f64]>)> = (0..blocks)
        .map(|b| {
            (
                b * size..((b + 1) * size).min(n),
                Vec::with_capacity(cols.len()),
            )
        })
        .collect();
    for (col, w) in cols.iter_mut().zip(widths) {
        let mut rest: &mut [f64] = col;
        for (rows, slices) in parts.iter_mut() {
            let take = if rest.is_empty() { 0 } else { rows.len() * w };
            let (head, tail) = std::mem::take(&mut rest).split_at_mut(take);
            slices.push(head);
            rest = tail;
        }
    }
    if blocks == 1 {
        let (rows, slices) = &mut parts[0];
        block(rows.clone(), slices)?;
    } else {
        parts
            .into_par_iter()
            .try_for_each(|(rows, mut slices)| block(rows, &mut slices))?;
    }
    Ok(cols)
}

/// Everything the position law needs for every row, checked.
struct PositionInputs {
    xs: Col,
    vs: Col,
    rs: Col,
    ws: Col,
    eip: Col,
    eia: Col,
    refs: Vec<Col>,
    p: RigidBodyParams<B>,
    pg: PositionGains<B>,
    ag: AttitudeGains<B>,
    model: AccelerationModel<B>,
    want: [bool; 12],
}

impl PositionInputs {
    /// The law over `rows`, written into `out` (the wanted columns'
    /// slices for those rows; empty for the others).
    fn run(&self, rows: std::ops::Range<usize>, out: &mut [&mut [f64]]) -> Result<(), RowError> {
        let first = rows.start;
        for i in rows {
            let state = VehicleState {
                x: v3(&self.xs, i),
                v: v3(&self.vs, i),
                r: So3Mat::<B>::from_matrix_unchecked(m3(&self.rs, i)),
                omega: v3(&self.ws, i),
            };
            let r = |k: usize| v3(&self.refs[k], i);
            let reference = PositionReference {
                x: r(0),
                v: r(1),
                a: r(2),
                jerk: r(3),
                snap: r(4),
                b1d: r(5),
                b1d_dot: r(6),
                b1d_ddot: r(7),
            };
            let input = PositionInput {
                state: &state,
                e_i_pos: v3(&self.eip, i),
                e_i_att: v3(&self.eia, i),
                reference: &reference,
                model: self.model,
            };
            let o = rs_position(&self.p, &self.pg, &self.ag, &input).map_err(|e| (i, e))?;
            let a3 = B::vec3_to_array;
            let rc: [f64; 9] = flat9(o.rc.matrix());
            let values: [&[f64]; 12] = [
                &[o.thrust],
                &a3(o.moment),
                &rc,
                &a3(o.omega_c),
                &a3(o.omega_c_dot),
                &a3(o.e_x),
                &a3(o.e_v),
                &a3(o.e_r),
                &a3(o.e_omega),
                &[o.psi],
                &a3(o.e_i_pos_rate),
                &a3(o.e_i_att_rate),
            ];
            let j = i - first;
            for ((col, on), v) in out.iter_mut().zip(&self.want).zip(values) {
                if *on {
                    col[j * v.len()..(j + 1) * v.len()].copy_from_slice(v);
                }
            }
        }
        Ok(())
    }
}

/// The position law (eqn:f, eqn:M with R_c, Ω_c, Ω̇_c from eqn:RdWc) for
/// each of the N states: `states` holds `x`, `v`, `R`, `omega`,
/// `e_i_pos`, `e_i_att`; `references` `x`, `v`, `a`, `jerk`, `snap`,
/// `b1d`, `b1d_dot`, `b1d_ddot` (each `(N, 3)` or `(3,)`; left out: zero,
/// `b1d` = e1).
#[pyfunction]
#[pyo3(signature = (states, references=None, gains_json=None, params=None, outputs=None))]
pub(crate) fn position_control<'py>(
    py: Python<'py>,
    states: &Bound<'py, PyDict>,
    references: Option<&Bound<'py, PyDict>>,
    gains_json: Option<&str>,
    params: Option<&Bound<'py, PyDict>>,
    outputs: Option<Vec<String>>,
) -> PyResult<Bound<'py, PyDict>> {
    let st = ["x", "v", "R", "omega", "e_i_pos", "e_i_att"];
    known_keys("states", Some(states), &st)?;
    let (n, xs) = required("states", states, "x", None, &[3])?;
    let (_, vs) = required("states", states, "v", Some(n), &[3])?;
    let (_, rs) = required("states", states, "R", Some(n), &[3, 3])?;
    let (_, ws) = required("states", states, "omega", Some(n), &[3])?;
    let eip = optional("states", Some(states), "e_i_pos", n, [0.0; 3])?;
    let eia = optional("states", Some(states), "e_i_att", n, [0.0; 3])?;
    let rn = ["x", "v", "a", "jerk", "snap", "b1d", "b1d_dot", "b1d_ddot"];
    known_keys("references", references, &rn)?;
    let refs = rn
        .iter()
        .map(|&name| {
            let default = if name == "b1d" {
                [1.0, 0.0, 0.0]
            } else {
                [0.0; 3]
            };
            optional("references", references, name, n, default)
        })
        .collect::<PyResult<Vec<_>>>()?;
    let g = gains(gains_json)?;
    let p = params_of(params)?;
    let mut pg = PositionGains::<B>::uniform(g.k_x, g.k_v, g.k_i, g.c1, g.sigma);
    pg.clamp_integral = g.clamp_integral;
    let ag = AttitudeGains::<B>::uniform(g.k_r, g.k_omega, g.k_att_i, g.c2);
    let model = match g.acceleration_model {
        AccelModel::Nominal => AccelerationModel::Nominal,
        AccelModel::NominalWithoutEstimate => AccelerationModel::NominalWithoutEstimate,
    };
    let want = selected(outputs, &POSITION_OUTPUTS)?;
    let inputs = PositionInputs {
        xs,
        vs,
        rs,
        ws,
        eip,
        eia,
        refs,
        p,
        pg,
        ag,
        model,
        want,
    };
    let cols = py
        .detach(|| {
            in_blocks(n, &POSITION_WIDTHS, &want, |rows, out| {
                inputs.run(rows, out)
            })
        })
        .map_err(|(i, e)| control_error(py, i, e))?;
    let names = POSITION_OUTPUTS;
    let d = PyDict::new(py);
    for (k, (name, data)) in names.iter().zip(cols).enumerate() {
        if !want[k] {
            continue;
        }
        let shape: &[usize] = match k {
            0 | 9 => &[n],
            2 => &[n, 3, 3],
            _ => &[n, 3],
        };
        d.set_item(name, array(py, shape, data)?)?;
    }
    Ok(d)
}

/// The attitude law (eqn:aM) for each of the N states: `states` holds
/// `R`, `omega`, `e_i`; `references` `Rd`, `omega_d`, `omega_d_dot`
/// (each `(N, …)` or one for all; left out: R_d = I, zero rates).
#[pyfunction]
#[pyo3(signature = (states, references=None, gains_json=None, params=None))]
pub(crate) fn attitude_control<'py>(
    py: Python<'py>,
    states: &Bound<'py, PyDict>,
    references: Option<&Bound<'py, PyDict>>,
    gains_json: Option<&str>,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    known_keys("states", Some(states), &["R", "omega", "e_i"])?;
    let (n, rs) = required("states", states, "R", None, &[3, 3])?;
    let (_, ws) = required("states", states, "omega", Some(n), &[3])?;
    let eis = optional("states", Some(states), "e_i", n, [0.0; 3])?;
    known_keys("references", references, &["Rd", "omega_d", "omega_d_dot"])?;
    let rds = match column("references", references, "Rd", Some(n), &[3, 3])? {
        Some((_, v)) => v,
        None => Col::one(&[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]),
    };
    let wd = optional("references", references, "omega_d", n, [0.0; 3])?;
    let wdd = optional("references", references, "omega_d_dot", n, [0.0; 3])?;
    let g = gains(gains_json)?;
    let p = params_of(params)?;
    let ag = AttitudeGains::<B>::uniform(g.k_r, g.k_omega, g.k_att_i, g.c2);
    let names = ["moment", "e_R", "e_omega", "psi", "e_i_rate"];
    let mut cols: Vec<Vec<f64>> = (0..names.len())
        .map(|_| Vec::with_capacity(3 * n))
        .collect();
    for i in 0..n {
        let reference = AttitudeReference {
            rd: So3Mat::<B>::from_matrix_unchecked(m3(&rds, i)),
            omega_d: v3(&wd, i),
            omega_d_dot: v3(&wdd, i),
        };
        let r = So3Mat::<B>::from_matrix_unchecked(m3(&rs, i));
        let o = rs_attitude(&p, &ag, r, v3(&ws, i), v3(&eis, i), &reference)
            .map_err(|e| control_error(py, i, e))?;
        push3(&mut cols[0], o.moment);
        push3(&mut cols[1], o.e_r);
        push3(&mut cols[2], o.e_omega);
        cols[3].push(o.psi);
        push3(&mut cols[4], o.e_i_rate);
    }
    let d = PyDict::new(py);
    for (k, (name, data)) in names.iter().zip(cols).enumerate() {
        let shape: &[usize] = if k == 3 { &[n] } else { &[n, 3] };
        d.set_item(name, array(py, shape, data)?)?;
    }
    Ok(d)
}
