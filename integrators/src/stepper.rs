//! Run-time choice of stepper.

use core::fmt;
use core::str::FromStr;

use lie::{Backend, Real, S};

use crate::{Dopri, Euler, Integrator, Lgvi, Rk4, Rkmk4, State, StepError, StepStats, System};

/// The steppers by name.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum IntegratorKind {
    /// `lgvi`
    Lgvi,
    /// `rk4`
    Rk4,
    /// `rk4-projected`
    Rk4Projected,
    /// `rkmk4`
    Rkmk4,
    /// `euler`
    Euler,
    /// `dopri`
    Dopri,
}

impl IntegratorKind {
    /// Every kind, in the order reports list them.
    pub const ALL: [IntegratorKind; 6] = [
        IntegratorKind::Lgvi,
        IntegratorKind::Rk4,
        IntegratorKind::Rk4Projected,
        IntegratorKind::Rkmk4,
        IntegratorKind::Euler,
        IntegratorKind::Dopri,
    ];

    /// The name accepted by [`FromStr`].
    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::Lgvi => "lgvi",
            IntegratorKind::Rk4 => "rk4",
            IntegratorKind::Rk4Projected => "rk4-projected",
            IntegratorKind::Rkmk4 => "rkmk4",
            IntegratorKind::Euler => "euler",
            IntegratorKind::Dopri => "dopri",
        }
    }
}

impl fmt::Display for IntegratorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A name that is not a stepper.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownIntegrator(pub String);

impl fmt::Display for UnknownIntegrator {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names: Vec<&str> = IntegratorKind::ALL.iter().map(|k| k.name()).collect();
        write!(
            f,
            "unknown integrator `{}`; expected one of {}",
            self.0,
            names.join(", ")
        )
    }
}

impl std::error::Error for UnknownIntegrator {}

impl FromStr for IntegratorKind {
    type Err = UnknownIntegrator;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        IntegratorKind::ALL
            .into_iter()
            .find(|k| k.name() == s)
            .ok_or_else(|| UnknownIntegrator(s.to_string()))
    }
}

/// Settings for steppers that have any.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct StepperConfig {
    /// Dormand–Prince tolerance (relative and absolute).
    pub tol: f64,
}

impl Default for StepperConfig {
    fn default() -> Self {
        Self { tol: 1e-10 }
    }
}

/// Any stepper, chosen at run time, for `N` extra states. Handed to a
/// simulation, which sizes its state itself, it is a [`Method`](crate::Method)
/// whose `N` does not matter: `Stepper::<B>::new(kind, config)` (`N` = 0)
/// says the kind and the settings.
#[derive(Clone, Debug)]
pub enum Stepper<B: Backend, const N: usize = 0> {
    /// See [`Lgvi`].
    Lgvi(Lgvi<B, N>),
    /// See [`Rk4`] (with or without projection).
    Rk4(Rk4),
    /// See [`Rkmk4`].
    Rkmk4(Rkmk4),
    /// See [`Euler`].
    Euler(Euler),
    /// See [`Dopri`].
    Dopri(Dopri<B>),
}

impl<B: Backend, const N: usize> Stepper<B, N> {
    /// The stepper of `kind`.
    pub fn new(kind: IntegratorKind, config: StepperConfig) -> Self {
        match kind {
            IntegratorKind::Lgvi => Stepper::Lgvi(Lgvi::default()),
            IntegratorKind::Rk4 => Stepper::Rk4(Rk4::default()),
            IntegratorKind::Rk4Projected => Stepper::Rk4(Rk4::projected()),
            IntegratorKind::Rkmk4 => Stepper::Rkmk4(Rkmk4),
            IntegratorKind::Euler => Stepper::Euler(Euler::default()),
            IntegratorKind::Dopri => Stepper::Dopri(Dopri::new(S::<B>::lit(config.tol))),
        }
    }

    /// The stepper called `name` (`lgvi`, `rk4`, `rk4-projected`, `rkmk4`,
    /// `euler`, `dopri`).
    pub fn from_name(name: &str, config: StepperConfig) -> Result<Self, UnknownIntegrator> {
        Ok(Self::new(name.parse()?, config))
    }
}

impl<B: Backend, const N: usize> Integrator<B, N> for Stepper<B, N> {
    fn name(&self) -> &'static str {
        match self {
            Stepper::Lgvi(s) => Integrator::<B, N>::name(s),
            Stepper::Rk4(s) => Integrator::<B, N>::name(s),
            Stepper::Rkmk4(s) => Integrator::<B, N>::name(s),
            Stepper::Euler(s) => Integrator::<B, N>::name(s),
            Stepper::Dopri(s) => Integrator::<B, N>::name(s),
        }
    }
    fn order(&self) -> u32 {
        match self {
            Stepper::Lgvi(s) => Integrator::<B, N>::order(s),
            Stepper::Rk4(s) => Integrator::<B, N>::order(s),
            Stepper::Rkmk4(s) => Integrator::<B, N>::order(s),
            Stepper::Euler(s) => Integrator::<B, N>::order(s),
            Stepper::Dopri(s) => Integrator::<B, N>::order(s),
        }
    }
    fn step<Sys: System<B, N> + ?Sized>(
        &mut self,
        sys: &mut Sys,
        t: S<B>,
        h: S<B>,
        y: &mut State<B, N>,
    ) -> Result<StepStats, StepError> {
        match self {
            Stepper::Lgvi(s) => s.step(sys, t, h, y),
            Stepper::Rk4(s) => s.step(sys, t, h, y),
            Stepper::Rkmk4(s) => s.step(sys, t, h, y),
            Stepper::Euler(s) => s.step(sys, t, h, y),
            Stepper::Dopri(s) => s.step(sys, t, h, y),
        }
    }
    fn reset(&mut self) {
        match self {
            Stepper::Lgvi(s) => Integrator::<B, N>::reset(s),
            Stepper::Dopri(s) => Integrator::<B, N>::reset(s),
            _ => {}
        }
    }
    fn limit_substeps(&mut self, cap: u32) {
        if let Stepper::Dopri(s) = self {
            Integrator::<B, N>::limit_substeps(s, cap);
        }
    }
    fn resampler(&self) -> Option<Self> {
        match self {
            Stepper::Dopri(s) => Some(Stepper::Dopri(s.clone())),
            _ => None,
        }
    }
}
