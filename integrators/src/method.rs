//! A method independent of the number of extra states, for callers that
//! size the state themselves.

use lie::Backend;

use crate::{Dopri, Euler, Integrator, Lgvi, Rk4, Rkmk4, Stepper};

/// An integration method before the number of extra states is known: a
/// simulation counts the states its plan and vehicle need, picks the
/// state's size, and asks the method for its [`Integrator`] at that size.
/// So a user chooses a method (and its settings) without choosing a slot
/// count.
///
/// Every stepper of this crate is one. A method of one's own whose
/// integrator works for any `N` (`impl<const N: usize> Integrator<B, N>`)
/// is one with `For<N> = Self`:
///
/// ```
/// use integrators::{Integrator, Method, Rk4, State, StepError, StepStats, System};
/// use lie::{Backend, S};
///
/// /// RK4 under another name.
/// #[derive(Clone)]
/// struct Mine(Rk4);
///
/// impl<B: Backend, const N: usize> Integrator<B, N> for Mine {
///     fn name(&self) -> &'static str {
///         "mine"
///     }
///     fn order(&self) -> u32 {
///         4
///     }
///     fn step<Sys: System<B, N> + ?Sized>(
///         &mut self,
///         sys: &mut Sys,
///         t: S<B>,
///         h: S<B>,
///         y: &mut State<B, N>,
///     ) -> Result<StepStats, StepError> {
///         self.0.step(sys, t, h, y)
///     }
/// }
///
/// impl<B: Backend> Method<B> for Mine {
///     type For<const N: usize> = Mine;
///     fn for_slots<const N: usize>(&self) -> Mine {
///         self.clone()
///     }
/// }
/// # let _ = <Mine as Method<lie::NalgebraF64>>::for_slots::<6>(&Mine(Rk4::default()));
/// ```
pub trait Method<B: Backend> {
    /// The integrator for `N` extra states (owning what it uses, so that
    /// a simulation can keep it for as long as it runs).
    type For<const N: usize>: Integrator<B, N> + 'static;
    /// That integrator, with this method's settings and nothing cached.
    fn for_slots<const N: usize>(&self) -> Self::For<N>;
}

/// Steppers that hold no per-state cache are their own integrator at
/// every size.
macro_rules! sized_by_any_n {
    ($($t:ty),*) => {$(
        impl<B: Backend> Method<B> for $t {
            type For<const N: usize> = $t;
            fn for_slots<const N: usize>(&self) -> $t {
                self.clone()
            }
        }
    )*};
}
sized_by_any_n!(Euler, Rk4, Rkmk4, Dopri<B>);

impl<B: Backend, const K: usize> Method<B> for Lgvi<B, K> {
    type For<const N: usize> = Lgvi<B, N>;
    fn for_slots<const N: usize>(&self) -> Lgvi<B, N> {
        let mut l = Lgvi::default();
        l.max_newton = self.max_newton;
        l.max_halvings = self.max_halvings;
        l.end_load = self.end_load;
        l
    }
}

impl<B: Backend, const K: usize> Method<B> for Stepper<B, K> {
    type For<const N: usize> = Stepper<B, N>;
    fn for_slots<const N: usize>(&self) -> Stepper<B, N> {
        match self {
            Stepper::Lgvi(s) => Stepper::Lgvi(s.for_slots()),
            Stepper::Rk4(s) => Stepper::Rk4(*s),
            Stepper::Rkmk4(s) => Stepper::Rkmk4(*s),
            Stepper::Euler(s) => Stepper::Euler(*s),
            Stepper::Dopri(s) => Stepper::Dopri(s.clone()),
        }
    }
}
