//! The predictor: the first guess of a step's curve — the system's own flow (on SO(3) by
//! quaternion, elsewhere in the step's chart), the previous curve continued, or the
//! velocity held — and the checks that a converged step is the motion's (not a step
//! too long for the chart, not an aliased root).

use super::*;

/// A continued curve whose residual is below this fraction of the equations' terms is
/// taken without trying the velocity-corrected predictor (Newton then needs ~2 steps).
pub(super) const PREDICTOR_GOOD_ENOUGH: f64 = 1e-3;

/// A continued curve whose relative residual is at or below this is taken instead of the
/// flow in the chart ([`crate::chart_flow::chart_flow`]): the flow's guess is typically
/// 1e-6 to 1e-5 (on the orbiting body), so below it the continued curve needs no more
/// Newton work.
pub(super) const CONTINUED_BEATS_FLOW: f64 = 1e-6;

/// While the flow in the chart wins, the continued curve is tried again every this many
/// steps (one assembly in this many steps wasted when it loses).
pub(super) const PROBE_CONTINUED: usize = 16;

impl<S: System<D>, C: GroupChart<S::Group, D>, const D: usize> Integrator<S, C, D> {
    /// Whether the next step is forced: the system has a force or the input is not zero.
    pub(super) fn forcing(&self) -> Option<SVector<f64, D>> {
        (self.system.is_forced()
            || self.point_inputs.is_some()
            || self.input.iter().any(|&u| u != 0.0))
        .then_some(self.input)
    }

    /// The predictor. When the system has a flow predictor (the SO(3) systems with `Ω(μ)`
    /// in closed form, under their forces and the control input): the system's own flow
    /// over the step
    /// ([`System::flow_guess`]; relative residual 3e-6 at `h = 0.5`
    /// and 2e-5 at `h = 1` on the paper's rigid body, against 3e-4 and 0.1 for the
    /// continued curve). Otherwise, after the first step: the last step's Galerkin curve
    /// continued ([`Integrator::extrapolate`]); if its relative residual exceeds
    /// [`PREDICTOR_GOOD_ENOUGH`] (long steps), the better of it and the previous step's
    /// chart coordinates corrected by the change of velocity,
    /// `ξⁱ ← ξⁱ_prev + A(0)⁻¹ t_i (ξ_k − ξ_{k−1})` (second order in `h`). On the first
    /// step, or with `constant_velocity`, `ξⁱ = Φ⁻¹(exp(t_i ξ_k))`: first order, but robust
    /// when the velocity changes a lot within a step (the fallback when Newton fails).
    ///
    /// Returns whether the guess is the constant-velocity one (nothing left to retry).
    ///
    /// # Errors
    /// [`MechanicsError::StepTooLong`] where the flow (or, without one, the present
    /// angular speed) turns the body past the chart's reach within the step.
    pub(super) fn predict(&mut self, constant_velocity: bool) -> Result<bool, MechanicsError> {
        self.work.guess_changed();
        if !constant_velocity {
            self.predictor.flow_end = None;
            let mut guess = self.predict_by_flow(false);
            if guess == FlowGuess::Unavailable {
                // Without a flow of its own: the flow in the chart (on the orbiting body
                // and on a free body in space it saves about one Newton matrix a step
                // against the continued curve, and an iteration on long steps),
                // unless the continued curve is already as good (a uniformly accelerated
                // body, where it is exact): it is tried first while it wins, and every
                // PROBE_CONTINUED steps while it does not.
                if self.predictor.previous_velocity.is_some()
                    && (self.predictor.continued_wins
                        || self.clock.step_index.is_multiple_of(PROBE_CONTINUED))
                    && self.extrapolate()
                {
                    if self.predictor_residual() <= CONTINUED_BEATS_FLOW {
                        self.predictor.continued_wins = true;
                        return Ok(false);
                    }
                    self.predictor.continued_wins = false;
                }
                guess = self.predict_by_flow(true);
            }
            match guess {
                FlowGuess::Written(end) => {
                    self.predictor.flow_end = Some(end);
                    return Ok(false);
                }
                FlowGuess::LeavesChart { time, angle } => {
                    return Err(self.step_too_long(angle, time));
                }
                FlowGuess::Unavailable => {
                    // Without the flow, the present angular speed bounds what a step
                    // must be able to turn.
                    let h = self.settings.h();
                    let rotation =
                        <S::Group as ConfigurationGroup<D>>::angular_speed(&self.state.velocity)
                            * h;
                    let limit = self.chart.max_rotation_angle();
                    if rotation >= limit {
                        return Err(self.step_too_long(rotation, h * limit / rotation));
                    }
                }
            }
        }
        if !constant_velocity && self.predictor.previous_velocity.is_some() && self.extrapolate() {
            // On long steps the continuation can be worse than the velocity correction
            // below: when its residual is not small, keep the better of the two.
            let continued = self.predictor_residual();
            if continued <= PREDICTOR_GOOD_ENOUGH {
                return Ok(false);
            }
            self.predictor.extrapolated.copy_from_slice(&self.work.xi);
            self.predict_from_velocity(false);
            let corrected = self.predictor_residual();
            if continued <= corrected {
                self.work.xi.copy_from_slice(&self.predictor.extrapolated);
                self.work.guess_changed();
            }
            return Ok(false);
        }
        self.predict_from_velocity(constant_velocity);
        Ok(constant_velocity || self.predictor.previous_velocity.is_none())
    }

    /// The error for a step that turns the body `rotation` rad, reaching the chart's
    /// limit `suggested` seconds into the step.
    pub(super) fn step_too_long(&self, rotation: f64, suggested: f64) -> MechanicsError {
        MechanicsError::StepTooLong {
            step: self.clock.step_index,
            time: self.state.time,
            chart: self.chart.name(),
            rotation,
            limit: self.chart.max_rotation_angle(),
            suggested,
            advice: self.chart.advice(),
        }
    }

    /// The error for a converged step `distance` rad away from the flow's end attitude.
    pub(super) fn aliased_root(&self, distance: f64) -> MechanicsError {
        MechanicsError::AliasedRoot {
            step: self.clock.step_index,
            time: self.state.time,
            chart: self.chart.name(),
            distance,
            advice: self.chart.advice(),
        }
    }

    /// The system's own flow over the step, when it has one (or, `in_chart`, the
    /// Euler–Poincaré flow in the step's chart, [`crate::chart_flow::chart_flow`]), under the
    /// step's total force (the system's and the control input).
    pub(super) fn predict_by_flow(&mut self, in_chart: bool) -> FlowGuess<ElementOf<S, D>> {
        self.work.guess_changed();
        let system = &self.system;
        let input = self.input;
        // The force the Gauss points see (the system's and the input), along the step.
        let force = StepForce::new(system, self.state.time, &input);
        let at = |time: f64| force.at(time);
        let total_force = |t: f64, g: &ElementOf<S, D>, xi: &SVector<f64, D>| at(t).jet(g, xi);
        // Its value alone (the jet's, bit for bit), for the flow's stages.
        let total_value = |t: f64, g: &ElementOf<S, D>, xi: &SVector<f64, D>| at(t).value(g, xi);
        let start = FlowStart {
            time: self.state.time,
            base: &self.state.configuration,
            momentum: &self.state.momentum,
            velocity: &self.state.velocity,
            h: self.settings.h(),
            times: self.discretisation.node_times(),
            force: self
                .forcing()
                .map(|_| &total_force as ForceAlongStep<'_, S::Group, D>),
            force_value: self
                .forcing()
                .map(|_| &total_value as ForceValueAlongStep<'_, S::Group, D>),
            force_reads_configuration: force.depends_on_configuration(),
        };
        let done = if in_chart {
            crate::chart_flow::chart_flow(system, &self.chart, &start, &mut self.work.xi)
        } else {
            system.flow_guess(&self.chart, &start, &mut self.work.xi)
        };
        self.work.xi[0] = SVector::zeros();
        done
    }

    /// The velocity-corrected (or, with `constant_velocity`, constant-velocity) predictor.
    pub(super) fn predict_from_velocity(&mut self, constant_velocity: bool) {
        self.work.guess_changed();
        let chart = self.chart;
        let a0_inv = chart
            .left_differential_inverse(&SVector::zeros())
            .unwrap_or_else(|_| SMatrix::identity());
        let omega = self.state.velocity;
        let times = self.discretisation.node_times();
        match self.predictor.previous_velocity {
            Some(previous) if !constant_velocity => {
                let change = a0_inv * (omega - previous);
                for (i, t) in times.iter().enumerate() {
                    self.work.xi[i] = self.predictor.last_nodes[i] + change * *t;
                }
            }
            _ => {
                for (i, t) in times.iter().enumerate() {
                    // On the branch of the linear guess: past a half turn per step, the
                    // principal logarithm would jump to the other side of the exp chart.
                    let linear = a0_inv * (omega * *t);
                    let moved = <S::Group as ConfigurationGroup<D>>::exp(&(omega * *t));
                    self.work.xi[i] = chart.to_algebra_near(&moved, &linear).unwrap_or(linear);
                }
            }
        }
        self.work.xi[0] = SVector::zeros();
    }

    /// The previous step's Galerkin curve continued over the next step, in the new
    /// step's chart: `ξⁱ = Φ⁻¹(Φ(ξⁿ_prev)⁻¹ Φ(ξ_prev(h + t_i)))`. False where a node
    /// leaves `Φ⁻¹`'s domain (the guess is then partly written: the caller replaces it).
    pub(super) fn extrapolate(&mut self) -> bool {
        let chart = self.chart;
        let n = self.discretisation.n;
        self.work.xi[0] = SVector::zeros();
        let end = chart.to_group(&self.predictor.last_nodes[n - 1]).inverse();
        for i in 1..n {
            let row = &self.discretisation.extrapolation[i * n..(i + 1) * n];
            let continued = row
                .iter()
                .zip(&self.predictor.last_nodes)
                .fold(SVector::<f64, D>::zeros(), |acc, (e, xi)| acc + xi * *e);
            // Each node on the branch of the one before (ξ¹ = 0): the continued curve may
            // rotate past a half turn relative to the step's start.
            let near = self.work.xi[i - 1];
            match chart.to_algebra_near(&end.compose(&chart.to_group(&continued)), &near) {
                Ok(xi) if xi.iter().all(|x| x.is_finite()) => self.work.xi[i] = xi,
                _ => return false,
            }
        }
        true
    }

    /// The relative residual of the guess in the workspace, from the current state.
    pub(super) fn predictor_residual(&mut self) -> f64 {
        let (base, mu) = (self.state.configuration, self.state.momentum);
        let (stepper, work) = self.stepper();
        stepper.relative_residual(&base, &mu, work)
    }
}
