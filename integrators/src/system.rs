//! The state and the system an integrator advances.

use lie::num_traits::Zero;
use lie::{Backend, M3, RigidState, S, V3, ops};

/// A rigid body plus `N` extra scalar states (integral terms of a
/// controller, say), advanced together.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct State<B: lie::SimdBackend, const N: usize> {
    /// Attitude (the matrix as integrated), position, velocity, angular
    /// velocity: the one rigid-body state of the workspace.
    pub body: RigidState<B, M3<B>>,
    /// Extra states.
    pub extra: [S<B>; N],
}

impl<B: Backend, const N: usize> State<B, N> {
    /// A body state with the extra states at zero.
    pub fn new(body: RigidState<B, M3<B>>) -> Self {
        Self {
            body,
            extra: [S::<B>::zero(); N],
        }
    }

    /// Every number of the state is finite: one branch-free test, inlined
    /// into each step's end (out of line, the new state was stored for it
    /// and read back).
    #[inline(always)]
    pub fn is_finite(&self) -> bool {
        let b = &self.body;
        ops::is_finite_mat::<B>(b.r)
            & ops::is_finite_vec::<B>(b.x)
            & ops::is_finite_vec::<B>(b.v)
            & ops::is_finite_vec::<B>(b.omega)
            & self
                .extra
                .iter()
                .fold(true, |ok, e| ok & lie::Real::is_finite(*e))
    }

    /// The first field that is not finite; the fields are told apart only
    /// when [`State::is_finite`] fails.
    pub(crate) fn non_finite_field(&self) -> Option<&'static str> {
        if self.is_finite() {
            return None;
        }
        if let Some(f) = self.body.non_finite_field() {
            return Some(f);
        }
        if self.extra.iter().any(|e| !lie::Real::is_finite(*e)) {
            return Some("extra");
        }
        None
    }
}

/// What a system exerts at a state: total inertial force (gravity, thrust,
/// disturbance), body moment without the gyroscopic term, and the extra
/// states' rates.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Load<B: lie::SimdBackend, const N: usize> {
    /// Inertial-frame force, N.
    pub force: V3<B>,
    /// Body-frame moment, N m (everything except `−Ω × JΩ`).
    pub moment: V3<B>,
    /// Time derivatives of the extra states.
    pub extra_rate: [S<B>; N],
}

impl<B: Backend, const N: usize> Load<B, N> {
    pub(crate) fn is_finite(&self) -> bool {
        // Branch-free (`&`): this runs at every evaluation.
        ops::is_finite_vec::<B>(self.force)
            & ops::is_finite_vec::<B>(self.moment)
            & self
                .extra_rate
                .iter()
                .fold(true, |ok, e| ok & lie::Real::is_finite(*e))
    }
}

/// A rigid body with loads: what every integrator advances.
///
/// The equations are `Ṙ = RΩ^`, `ẋ = v`, `m v̇ = force`,
/// `J Ω̇ = moment − Ω × JΩ`, `ė = extra_rate`; when [`System::translates`]
/// is false, `x` and `v` are left alone and cost nothing.
///
/// # Example
/// A falling body whose one extra state integrates its height: after 1 s
/// of free fall from rest (e3 down), `x3 = g/2` and the extra state holds
/// `∫x3 dt = g/6`, both polynomials RK4 integrates exactly.
///
/// ```
/// use integrators::{Load, Rk4, State, System, integrate_fixed};
/// use lie::{Backend, GlamF64, M3, RigidState, ops};
/// type B = GlamF64;
///
/// struct Falling;
/// impl System<B, 1> for Falling {
///     fn mass(&self) -> f64 { 2.0 }
///     fn inertia(&self) -> M3<B> { ops::identity::<B>() }
///     fn load(&mut self, _t: f64, y: &State<B, 1>) -> Load<B, 1> {
///         Load {
///             force: B::vec3(0.0, 0.0, 2.0 * 9.81),
///             moment: B::vec3(0.0, 0.0, 0.0),
///             extra_rate: [B::vec3_to_array(y.body.x)[2]],
///         }
///     }
/// }
/// let mut y = State::<B, 1>::new(RigidState::at_rest());
/// integrate_fixed(&mut Rk4::default(), &mut Falling, 0.0, 0.1, 10, &mut y)?;
/// assert!((B::vec3_to_array(y.body.x)[2] - 9.81 / 2.0).abs() < 1e-12);
/// assert!((y.extra[0] - 9.81 / 6.0).abs() < 1e-12);
/// # Ok::<(), integrators::StepError>(())
/// ```
pub trait System<B: Backend, const N: usize> {
    /// Mass, kg.
    fn mass(&self) -> S<B>;
    /// Inertia, body frame.
    fn inertia(&self) -> M3<B>;
    /// `J⁻¹`; override to return a cached value (the default inverts
    /// `inertia()` on every call). A singular inertia has no inverse: the
    /// default returns NaN, so the first step fails with a non-finite state
    /// instead of integrating with a made-up inertia.
    fn inertia_inv(&self) -> M3<B> {
        inverse_or_nan::<B>(self.inertia())
    }
    /// Whether `x` and `v` are integrated.
    fn translates(&self) -> bool {
        true
    }
    /// Whether [`System::load`] reads `v`, `Ω` or the extra states (feedback
    /// control does). If not, the LGVI evaluates its end-point load once
    /// instead of iterating.
    fn load_depends_on_rates(&self) -> bool {
        true
    }
    /// How many of the `N` extra slots hold states (the first ones; the
    /// rest stay zero). Dormand–Prince's error norm averages over these
    /// only, so a system's steps do not depend on how many idle slots its
    /// state type carries. The default is all `N`.
    fn extra_in_use(&self) -> usize {
        N
    }
    /// Loads at time `t` and state `y`.
    fn load(&mut self, t: S<B>, y: &State<B, N>) -> Load<B, N>;
}

/// `m⁻¹`, or all NaN for a singular `m` (see [`System::inertia_inv`]):
/// what a [`System`] caching its inverse inertia stores.
pub fn inverse_or_nan<B: Backend>(m: M3<B>) -> M3<B> {
    ops::inverse::<B>(m).unwrap_or_else(|| {
        let nan = <S<B> as lie::Real>::nan();
        ops::diag::<B>(nan, nan, nan) * nan
    })
}
