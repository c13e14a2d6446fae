//! The exact linearisation of a step at its converged solution (implicit function
//! theorem on the Newton matrix): `A = ∂x₊/∂x`, `B = ∂x₊/∂u`.

use super::*;

impl<S: System<D>, C: GroupChart<S::Group, D>, const D: usize> Integrator<S, C, D> {
    /// The exact linearisation of the step from the current state with the current input
    /// ([`StepLinearization`]: `A = ∂x₊/∂x`, `B = ∂x₊/∂u`), without taking the step: the
    /// state, the step count and the statistics are unchanged. An adaptive run
    /// linearises the step at its present nodes and step.
    ///
    /// ```
    /// use lgsvi_mechanics::{Inertia, Integrator, RigidBody, StepSettings};
    /// use lgsvi_mechanics::linearization::Coordinates;
    /// use lgsvi_mechanics::lie::SO3;
    /// use nalgebra::Vector3;
    /// // A body at rest: the step is the exact zero-order hold of θ̈ = J⁻¹u.
    /// let body = RigidBody::new(Inertia::from_principal_moments([1.0, 2.0, 2.5])?);
    /// let h = 0.1;
    /// let mut integrator = Integrator::new(body, StepSettings::new(h, 4)?, SO3::identity(), Vector3::zeros())?;
    /// let step = integrator.linearize()?;
    /// let (a, b) = (step.a(Coordinates::Velocity), step.b(Coordinates::Velocity));
    /// assert!((a[(2, 5)] - h).abs() < 1e-15); // θ₊ = θ + hω + …
    /// assert!((b[(5, 2)] - h / 2.5).abs() < 1e-15); // ω₊ = ω + hJ⁻¹u
    /// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
    /// ```
    ///
    /// # Errors
    /// Those of [`Integrator::step`]; [`MechanicsError::InvalidSetting`] under the
    /// paper's matching (not variational: no linearisation is offered).
    pub fn linearize(&mut self) -> Result<StepLinearization<ElementOf<S, D>, D>, MechanicsError> {
        self.linearize_from_start(false)
    }

    /// Takes one step (as [`Integrator::step`]) and returns its exact linearisation
    /// ([`StepLinearization`]), at the cost of one more Newton matrix and its
    /// factorisation, and a few back-substitutions: the Newton loop keeps the Hessians of
    /// its last assembly, at the rounding floor, for that matrix (usually: a loop whose
    /// last assembly was gradient-only leaves the linearisation one more assembly). The step is
    /// [`Integrator::step`]'s bit for bit for an unforced system with a left-invariant
    /// Lagrangian and to rounding (a few ulps) otherwise: an assembly with Hessians forms
    /// the matching's transport as a matrix.
    ///
    /// # Errors
    /// As [`Integrator::linearize`]; if only the linearisation fails, the step has been
    /// taken.
    pub fn step_linearized(
        &mut self,
    ) -> Result<StepLinearization<ElementOf<S, D>, D>, MechanicsError> {
        self.step_and_linearize(false)
    }

    /// [`Integrator::linearize`] with the derivatives in the system's physical parameters
    /// as well ([`StepLinearization::p`]: the inertia tensor's entries and, where the
    /// system has one, its mass; [`crate::System::parameter_names`]), exact to
    /// rounding by the same implicit function theorem: each parameter adds a gradient-only
    /// assembly of `ℓ`'s derivative in it and a back-substitution with the same fresh
    /// factors. Forces do not depend on the parameters. A scratch workspace is allocated
    /// per call.
    ///
    /// ```
    /// use lgsvi_mechanics::{Inertia, Integrator, RigidBody, StepSettings};
    /// use lgsvi_mechanics::linearization::Coordinates;
    /// use lgsvi_mechanics::lie::SO3;
    /// use nalgebra::Vector3;
    /// // A body at rest under a torque u: ω₊ = h J⁻¹u, so ∂ω₊/∂J_zz = −h u_z / J_zz².
    /// let body = RigidBody::new(Inertia::from_principal_moments([1.0, 2.0, 2.5])?);
    /// let (h, u) = (0.1, Vector3::new(0.0, 0.0, 0.3));
    /// let mut integrator = Integrator::new(body, StepSettings::new(h, 4)?, SO3::identity(), Vector3::zeros())?;
    /// integrator.set_input(u)?;
    /// let step = integrator.linearize_with_parameters()?;
    /// assert_eq!(step.parameter_names()[2], "J_zz");
    /// let p = step.p(Coordinates::Velocity).unwrap();
    /// assert!((p[(5, 2)] + h * 0.3 / 2.5f64.powi(2)).abs() < 1e-15);
    /// # Ok::<(), lgsvi_mechanics::MechanicsError>(())
    /// ```
    ///
    /// # Errors
    /// As [`Integrator::linearize`].
    pub fn linearize_with_parameters(
        &mut self,
    ) -> Result<StepLinearization<ElementOf<S, D>, D>, MechanicsError> {
        self.linearize_from_start(true)
    }

    /// [`Integrator::step_linearized`] with the derivatives in the system's parameters,
    /// as [`Integrator::linearize_with_parameters`].
    ///
    /// # Errors
    /// As [`Integrator::step_linearized`].
    pub fn step_linearized_with_parameters(
        &mut self,
    ) -> Result<StepLinearization<ElementOf<S, D>, D>, MechanicsError> {
        self.step_and_linearize(true)
    }

    /// [`Integrator::linearize`], with the parameter columns if `parameters`.
    fn linearize_from_start(
        &mut self,
        parameters: bool,
    ) -> Result<StepLinearization<ElementOf<S, D>, D>, MechanicsError> {
        let start = self.state;
        // A linearisation at the state is a function of the state alone, and leaves the
        // run as it found it: the run's factors are set aside while it solves the step
        // from fresh ones, and taken back after.
        self.work.park_factors();
        self.linearizing = true;
        let outcome = self.attempt(&start.configuration);
        self.linearizing = false;
        let linearization = outcome
            .and_then(|outcome| self.end_state(&outcome))
            .and_then(|end| self.linearization_of(start, end, parameters));
        self.work.unpark_factors();
        // A singular linearisation has the causes of a failed step (a Lagrangian not
        // strictly convex in the velocity at the state, …), named the same way.
        linearization.map_err(|error| self.diagnose(error))
    }

    /// [`Integrator::step_linearized`], with the parameter columns if `parameters`.
    fn step_and_linearize(
        &mut self,
        parameters: bool,
    ) -> Result<StepLinearization<ElementOf<S, D>, D>, MechanicsError> {
        let start = self.state;
        self.linearizing = true;
        let taken = self.step();
        self.linearizing = false;
        taken?;
        let end = self.state;
        self.linearization_of(start, end, parameters)
            .map_err(|error| self.diagnose(error))
    }

    /// The linearisation of the step just solved (its unknowns in the workspace) from
    /// `start` to `end`, with the parameter columns if `parameters`.
    fn linearization_of(
        &mut self,
        start: State<ElementOf<S, D>, D>,
        end: State<ElementOf<S, D>, D>,
        parameters: bool,
    ) -> Result<StepLinearization<ElementOf<S, D>, D>, MechanicsError> {
        let stepper = StepSolver {
            system: &self.system,
            chart: &self.chart,
            settings: &self.settings,
            d: &self.discretisation,
            time: start.time,
            forcing: self.forcing(),
            point_inputs: self.point_inputs.as_deref(),
        };
        let index = self.clock.step_index;
        let jacobians =
            stepper.linearize(&start.configuration, &start.momentum, &mut self.work, index)?;
        let parameter_jacobians = if parameters {
            let mut scratch = crate::step::assembly::Workspace::new(&self.discretisation);
            Some(stepper.parameter_jacobians(
                &start.configuration,
                &self.work,
                &mut scratch,
                index,
            )?)
        } else {
            None
        };
        let point_jacobians = if self.point_inputs.is_some() {
            Some(stepper.point_input_jacobians(&self.work, index)?)
        } else {
            None
        };
        StepLinearization::new(
            &self.system,
            &jacobians,
            start,
            end,
            self.input,
            (self.settings.h(), self.discretisation.n, index),
            parameter_jacobians,
            point_jacobians,
        )
    }
}
