//! One step: attempt (predict, solve, estimate), node and step control (more nodes or a
//! shorter step on failure, fewer nodes once the error allows), and commit (the state,
//! the ledger of statistics and sums, the work of the forces).

use super::*;

/// A converged step whose end attitude is further than this (radians) from the system's
/// own flow over the step is an aliased root. The flow's error is ~1e-5 of the step's
/// rotation (see [`crate::flow`]) and a converged step's local error far below 0.1 rad on
/// any step that converges to the motion, while an aliased root is off by an O(1) turn.
const ALIASED_DISTANCE: f64 = 0.5;

/// After a step had to be solved again with more nodes, the nodes stay up for this many
/// steps before they may fall, twice as long after each fall that failed (up to
/// [`NODES_HOLD_MAX`]): where the error varies along the motion (the heavy top), lowering
/// them at once would solve about every sixth step twice (case B at `h = 0.5` and 6e-13
/// per unit time).
pub(super) const NODES_HOLD: usize = 8;
pub(super) const NODES_HOLD_MAX: usize = 1024;

/// The most times one step is halved when step changes are allowed.
pub(super) const MAX_HALVINGS: usize = 30;

/// A failure of the step's solve (Newton, the chart, the inverse Legendre transform), which
/// the system's state may explain ([`Integrator::diagnose`]).
fn is_solve_failure(error: &MechanicsError) -> bool {
    matches!(
        error,
        MechanicsError::NewtonDiverged { .. }
            | MechanicsError::SingularJacobian { .. }
            | MechanicsError::InverseLegendre { .. }
            | MechanicsError::OutsideChart { .. }
            | MechanicsError::StepTooLong { .. }
            | MechanicsError::AliasedRoot { .. }
    )
}

impl<S: System<D>, C: GroupChart<S::Group, D>, const D: usize> Integrator<S, C, D> {
    /// Advances one step; returns the Newton iterations it took.
    ///
    /// # Errors
    /// [`MechanicsError::NewtonDiverged`], [`MechanicsError::SingularJacobian`] or
    /// [`MechanicsError::OutsideChart`], naming the step;
    /// [`MechanicsError::StepTooLong`] where the motion turns the body past the chart's
    /// reach ([`GroupChart::max_rotation_angle`]) within the step, and
    /// [`MechanicsError::AliasedRoot`] where Newton converged to an attitude that is not
    /// the continuation of the motion (checked against the system's own flow, when it
    /// has one). The state is left unchanged. Where a step fails (any of these) because `ℓ` is not strictly convex in the velocity at the state (a zero or
    /// negative inertia or mass, after [`Integrator::system_mut`] for instance), the error
    /// is [`MechanicsError::DegenerateLagrangian`] instead, which no step or node count
    /// mends; and where it fails at a state outside what the system models (an
    /// [`crate::OrbitingBody`] whose mass surrounds the attracting point), the error is
    /// [`MechanicsError::OutsideModel`], naming what to change.
    pub fn step(&mut self) -> Result<usize, MechanicsError> {
        self.advance().map_err(|error| self.diagnose(error))
    }

    /// The cause of a failed step, when it is the system's: `∂²ℓ/∂ξ²` at the state not
    /// positive definite, or a state outside what the system models
    /// ([`System::model_breakdown`]). Read only on this error path.
    pub(super) fn diagnose(&self, error: MechanicsError) -> MechanicsError {
        let solve = is_solve_failure(&error);
        if !(solve
            || matches!(
                error,
                MechanicsError::NonFiniteStep { .. } | MechanicsError::ToleranceNotMet { .. }
            ))
        {
            return error;
        }
        let state = &self.state;
        let (degenerate, least, most) = self.hessian_spectrum();
        if let Some(degenerate) = degenerate {
            return degenerate;
        }
        if let Some(reason) =
            self.system
                .model_breakdown(state.time, &state.configuration, &state.velocity)
        {
            return MechanicsError::OutsideModel {
                step: self.clock.step_index,
                time: state.time,
                reason,
                failure: Box::new(error),
            };
        }
        // A step that fails where the velocity is barely determined by the momentum: the
        // conditioning is the cause (shorter steps may converge, to that accuracy only).
        if solve && least > 0.0 && most >= crate::error::ILL_CONDITIONED * least {
            return MechanicsError::IllConditioned {
                step: self.clock.step_index,
                time: state.time,
                least,
                most,
                failure: Box::new(error),
            };
        }
        error
    }

    /// [`MechanicsError::DegenerateLagrangian`] where `∂²ℓ/∂ξ²` at the state is not
    /// positive definite, and that matrix's least and largest eigenvalues (`NaN` where it
    /// is not finite).
    ///
    /// Convexity does not depend on units, so the test reads the Hessian scaled to a unit
    /// diagonal, `D^{-1/2} H D^{-1/2}`: a mass of 1e-30 beside an inertia of 1 is a badly
    /// scaled but convex Lagrangian (its failure is the model's or the step's), while a
    /// zero or negative diagonal, or a scaled eigenvalue at rounding, is degenerate. The
    /// message gives `H`'s own eigenvalues.
    fn hessian_spectrum(&self) -> (Option<MechanicsError>, f64, f64) {
        let state = &self.state;
        let (_, hessian) = crate::state::legendre_blocks(
            &self.system,
            state.time,
            &state.configuration,
            &state.velocity,
        );
        let symmetric = (hessian + hessian.transpose()) * 0.5;
        if symmetric.iter().any(|x| !x.is_finite()) {
            return (None, f64::NAN, f64::NAN);
        }
        // Dynamic storage: the fixed-size eigen decomposition needs bounds a const `D` lacks.
        let range = |matrix: nalgebra::DMatrix<f64>| {
            matrix
                .symmetric_eigenvalues()
                .iter()
                .fold((f64::INFINITY, 0.0f64), |(l, m), &e| {
                    (l.min(e), m.max(e.abs()))
                })
        };
        let unscaled = nalgebra::DMatrix::from_iterator(D, D, symmetric.iter().copied());
        let diagonal = unscaled.diagonal();
        let degenerate = if diagonal.iter().all(|&d| d > 0.0) {
            let scale = diagonal.map(|d| d.sqrt().recip());
            let scaled = unscaled.component_mul(&(&scale * scale.transpose()));
            let (least, most) = range(scaled);
            least <= f64::EPSILON * D as f64 * most
        } else {
            true
        };
        let (least, most) = range(unscaled);
        let error = degenerate.then_some(MechanicsError::DegenerateLagrangian {
            step: self.clock.step_index,
            time: state.time,
            least,
            most,
        });
        (error, least, most)
    }

    pub(super) fn advance(&mut self) -> Result<usize, MechanicsError> {
        let Some(adaptive) = self.settings.adaptive() else {
            let base = self.state.configuration;
            let outcome = self.attempt(&base)?;
            let (estimate, _) = self.discretisation.error_estimate(&self.work.xi);
            return self.commit(&base, outcome, estimate.max(ROUNDING_FLOOR));
        };
        if let Some(h) = self.control.next_step.take() {
            self.switch_step(h)?;
        }
        if let Some(n) = self.control.next_nodes.take() {
            self.switch_nodes(n)?;
        }
        let base = self.state.configuration;
        let mut halvings = 0;
        loop {
            let budget = adaptive.rate * self.settings.h();
            let outcome = match self.attempt(&base) {
                Ok(outcome) => outcome,
                // A step the chart cannot follow, or that Newton cannot solve, is tried
                // again at half the step when the step may change.
                Err(_) if adaptive.step_changes && halvings < MAX_HALVINGS => {
                    halvings += 1;
                    self.ledger.statistics.rejected_steps += 1;
                    self.switch_step(0.5 * self.settings.h())?;
                    continue;
                }
                Err(error) => return Err(error),
            };
            // Whether the step meets its share reads the estimate floored at the rounding
            // of a step (no nodes make it smaller); the choice of the next nodes and step
            // reads the spectral estimate itself.
            let (estimate, decay) = self.discretisation.error_estimate(&self.work.xi);
            let floored = estimate.max(ROUNDING_FLOOR);
            let n = self.discretisation.n;
            if floored > budget && n < adaptive.max_nodes {
                // A step that lowered its nodes and failed doubles the wait before the
                // next try (where the error varies along the motion, a fall that fails
                // once tends to fail again soon).
                self.control.hold_length = if self.control.lowered {
                    (2 * self.control.hold_length).min(NODES_HOLD_MAX)
                } else {
                    NODES_HOLD
                };
                self.control.hold_nodes = self.control.hold_length;
                self.control.lowered = false;
                // The estimate falls by about q² per node: add the nodes that bring it
                // under the budget (at least one, at most four at a time).
                let wanted = if decay < 1.0 && decay > 0.0 {
                    ((budget / estimate).ln() / (decay * decay).ln()).ceil()
                } else {
                    2.0
                };
                let more = (wanted as usize).clamp(1, 4);
                self.count_redone(&outcome);
                self.switch_nodes((n + more).min(adaptive.max_nodes))?;
                continue;
            }
            if floored > budget && adaptive.step_changes && halvings < MAX_HALVINGS {
                // The most nodes allowed do not reach the tolerance: half the step.
                halvings += 1;
                self.count_redone(&outcome);
                self.switch_step(0.5 * self.settings.h())?;
                continue;
            }
            if floored > budget {
                // Every remedy spent: accepting the step would miss the tolerance quietly.
                let (halved, advice) = if adaptive.step_changes {
                    (
                        format!(
                            ", after halving the step {halvings} times to {:e}",
                            self.settings.h()
                        ),
                        "the tolerance is below what this motion allows in double precision: \
                         raise it",
                    )
                } else {
                    (
                        String::new(),
                        "raise the tolerance, allow more nodes, shorten the step h, or let the \
                         step change",
                    )
                };
                return Err(MechanicsError::ToleranceNotMet {
                    step: self.clock.step_index,
                    time: self.state.time,
                    estimate: floored,
                    budget,
                    nodes: n,
                    halved,
                    advice,
                });
            }
            let iterations = self.commit(&base, outcome, floored)?;
            if std::mem::take(&mut self.control.lowered) {
                // The fall held: the next wait starts short again.
                self.control.hold_length = NODES_HOLD;
            }
            // The next step's estimate, extrapolated from this one and the one before when
            // the error grows along the motion: where it would exceed the budget, the next
            // step takes one node more now rather than being solved twice.
            let growth = if self.control.previous_estimate > 0.0
                && estimate > 1.5 * self.control.previous_estimate
            {
                (estimate / self.control.previous_estimate).min(1e3)
            } else {
                1.0
            };
            self.control.previous_estimate = estimate;
            let expected = estimate * growth;
            self.control.hold_nodes = self.control.hold_nodes.saturating_sub(1);
            if expected > budget && n < adaptive.max_nodes {
                self.control.next_nodes = Some(n + 1);
            } else if adaptive.falling_nodes
                && self.control.hold_nodes == 0
                && n > adaptive.min_nodes
                && decay > 0.0
                && decay < 1.0
                && expected > 0.0
            {
                // Each node fewer multiplies the estimate by about 1/q²: the next step
                // takes as few as keep it under half the budget (the margin keeps n from
                // going back and forth between neighbours).
                let fewer = ((0.5 * budget / expected).ln() / (decay * decay).recip().ln())
                    .floor()
                    .max(0.0) as usize;
                let next = n.saturating_sub(fewer.min(4)).max(adaptive.min_nodes);
                if next < n {
                    self.control.next_nodes = Some(next);
                    self.control.lowered = true;
                }
            }
            // With room below the budget, the step may grow back: doubling it multiplies
            // the local error by about 2^(2n−1) (order 2(n−1)) and the budget by 2; it
            // doubles where that stays under half the new budget.
            let h = self.settings.h();
            if adaptive.step_changes
                && self.control.next_nodes.is_none_or(|next| next <= n)
                && h < self.control.largest_step
                && expected * 2f64.powi(2 * n as i32 - 1) < budget
            {
                self.control.next_step = Some((2.0 * h).min(self.control.largest_step));
            }
            return Ok(iterations);
        }
    }

    /// Counts a solve that is thrown away and redone: its Newton work stays in the
    /// statistics.
    pub(super) fn count_redone(&mut self, outcome: &StepOutcome<ElementOf<S, D>, D>) {
        let stats = &mut self.ledger.statistics;
        stats.rejected_steps += 1;
        stats.newton_iterations += outcome.iterations;
        stats.factorizations += outcome.factorizations;
    }

    /// Moves the integrator to the step `h` (same nodes, so the workspace stays): times
    /// are counted from the present state, and the last step's curve, made for the old
    /// step, no longer seeds the predictor.
    pub(super) fn switch_step(&mut self, h: f64) -> Result<(), MechanicsError> {
        if h == self.settings.h() {
            return Ok(());
        }
        if !(h.is_finite() && h >= crate::settings::STEP_RANGE.0) {
            return Err(MechanicsError::InvalidSetting {
                name: "h",
                value: format!("{h:?}"),
                reason: "the step fell below 1e-280 while halving: the tolerance cannot be met",
            });
        }
        let settings = self.settings.with_step_unchecked(h);
        self.discretisation = Discretisation::shared(&settings)?;
        // The Newton matrix scales with the step: factors of another step say nothing.
        self.work.forget_factors();
        self.settings = settings;
        self.clock.origin = self.state.time;
        self.clock.origin_steps = self.clock.step_index;
        self.predictor.previous_velocity = None;
        self.control.previous_estimate = 0.0;
        Ok(())
    }

    /// Moves the integrator to `n` nodes (tables, workspace, and the last step's curve
    /// resampled on the new nodes for the predictor). A workspace is built the first time
    /// a node count is used and kept for later.
    pub(super) fn switch_nodes(&mut self, n: usize) -> Result<(), MechanicsError> {
        if n == self.discretisation.n {
            return Ok(());
        }
        let settings = self.settings.with_nodes(n);
        let tables = Discretisation::shared(&settings)?;
        let mut work = match self.spare_work.iter().position(|w| w.xi.len() == n) {
            Some(i) => self.spare_work.swap_remove(i),
            None => Workspace::new(&tables),
        };
        // A kept workspace's factors are of a step at another time.
        work.forget_factors();
        let previous = std::mem::replace(&mut self.work, work);
        self.spare_work.push(previous);
        // The last curve on the new nodes: exact when n grows (a polynomial of lower
        // degree), its interpolant when n shrinks (used only as the predictor's start).
        // The buffers hold `max_nodes` from the integrator's construction: no allocation.
        self.predictor.resampled.clear();
        self.predictor
            .basis_values
            .resize(self.discretisation.n, 0.0);
        for &t in tables.node_times() {
            self.discretisation
                .basis
                .basis_into(t, &mut self.predictor.basis_values)?;
            let value = self
                .predictor
                .basis_values
                .iter()
                .zip(&self.predictor.last_nodes)
                .fold(SVector::zeros(), |acc, (c, x)| acc + x * *c);
            self.predictor.resampled.push(value);
        }
        std::mem::swap(
            &mut self.predictor.last_nodes,
            &mut self.predictor.resampled,
        );
        self.predictor.extrapolated.resize(n, SVector::zeros());
        self.discretisation = tables;
        self.settings = settings;
        Ok(())
    }

    /// Predicts and solves the step from `base` (the current state), without taking it.
    pub(super) fn attempt(
        &mut self,
        base: &ElementOf<S, D>,
    ) -> Result<StepOutcome<ElementOf<S, D>, D>, MechanicsError> {
        let constant_velocity = self.predict(false)?;
        let first = self.solve(base);
        let outcome = match first {
            Ok(outcome) => outcome,
            // A poor guess (the velocity changed a lot over the last step, or the flow
            // guess led Newton astray): retry once from constant velocity before giving up.
            Err(_) if !constant_velocity => {
                self.predict(true)?;
                self.solve(base)?
            }
            Err(error) => return Err(error),
        };
        if let Some(end) = self.predictor.flow_end {
            let difference = end
                .inverse()
                .compose(&base.inverse())
                .compose(&outcome.configuration);
            let distance = <S::Group as ConfigurationGroup<D>>::rotation_angle(&difference);
            if distance.is_nan() || distance > ALIASED_DISTANCE {
                return Err(self.aliased_root(distance));
            }
        }
        Ok(outcome)
    }

    /// The state a solved step ends at: the configuration renormalised, the step's end
    /// time, the momentum and its velocity.
    ///
    /// # Errors
    /// [`MechanicsError::NonFiniteStep`] for a non-finite momentum; those of
    /// [`body_velocity`].
    pub(super) fn end_state(
        &self,
        outcome: &StepOutcome<ElementOf<S, D>, D>,
    ) -> Result<State<ElementOf<S, D>, D>, MechanicsError> {
        // g_k Φ(ξⁿ) is on the group up to the rounding of the product, which would
        // accumulate over millions of steps (‖RᵀR − I‖ 1e-12 after 10⁶ steps without it);
        // one polar Newton step R(I + ½(I − RᵀR)) squares that deviation away.
        let configuration =
            <S::Group as ConfigurationGroup<D>>::renormalise(&outcome.configuration);
        let since = self.clock.step_index + 1 - self.clock.origin_steps;
        let time = self.clock.origin + since as f64 * self.settings.h();
        let velocity = body_velocity(
            &self.system,
            time,
            &outcome.configuration,
            &outcome.momentum,
            &self.state.velocity,
        )?;
        if !outcome.momentum.iter().all(|x| x.is_finite()) {
            return Err(MechanicsError::NonFiniteStep {
                step: self.clock.step_index,
                time: self.state.time,
                what: "the momentum after the step",
                hint: if self.forcing().is_some() {
                    "the force (the system's or the input) or the Lagrangian gave a non-finite \
                     value within this step, or the inputs overflow double precision: check \
                     them at this time"
                } else {
                    "the Lagrangian or its derivatives gave a non-finite value within this \
                     step, or the inputs overflow double precision: check them at this state"
                },
            });
        }
        Ok(State {
            time,
            configuration,
            momentum: outcome.momentum,
            velocity,
        })
    }

    /// Takes the solved step: the new state, the work done, the statistics.
    pub(super) fn commit(
        &mut self,
        base: &ElementOf<S, D>,
        outcome: StepOutcome<ElementOf<S, D>, D>,
        estimate: f64,
    ) -> Result<usize, MechanicsError> {
        let end = self.end_state(&outcome)?;
        // A step that converged to a state the model does not hold at is not taken: its
        // end, and every step after it, would integrate equations that do not describe
        // the system (an orbiting body flung out of a fall through its own far field).
        if let Some(reason) =
            self.system
                .model_breakdown(end.time, &end.configuration, &end.velocity)
        {
            return Err(MechanicsError::LeftModel {
                step: self.clock.step_index,
                time: self.state.time,
                reason,
            });
        }
        if let Some(input) = self.forcing() {
            let work = self.step_work(base, self.state.time, &input);
            self.ledger.work.add(work);
        }
        self.predictor.last_base = self.state.configuration;
        self.predictor.last_nodes.copy_from_slice(&self.work.xi);
        self.predictor.previous_velocity = Some(self.state.velocity);
        self.clock.step_index += 1;
        self.state = end;
        let stats = &mut self.ledger.statistics;
        stats.steps += 1;
        stats.newton_iterations += outcome.iterations;
        stats.factorizations += outcome.factorizations;
        stats.max_newton_iterations = stats.max_newton_iterations.max(outcome.iterations);
        self.ledger.nodes_used[self.discretisation.n] += 1;
        self.ledger.estimate = estimate;
        self.ledger.estimates.add(estimate);
        Ok(outcome.iterations)
    }

    pub(super) fn solve(
        &mut self,
        base: &ElementOf<S, D>,
    ) -> Result<StepOutcome<ElementOf<S, D>, D>, MechanicsError> {
        let (mu, step, time) = (self.state.momentum, self.clock.step_index, self.state.time);
        if let Some(points) = &self.point_inputs {
            if points.len() != self.discretisation.m {
                return Err(MechanicsError::InvalidSetting {
                    name: "input_at_points",
                    value: format!(
                        "{} inputs for {} Gauss points ({} nodes)",
                        points.len(),
                        self.discretisation.m,
                        self.discretisation.n
                    ),
                    reason: "the node count changed since the inputs were set per Gauss point: \
                             set them again (or a constant input) for the new node count",
                });
            }
        }
        // Only the exact matching's step has a linearisation (the Newton loop itself keeps
        // Hessians only where its matrix is the exact one).
        let linearizing =
            self.linearizing && self.settings.matching() == crate::settings::Matching::Exact;
        let (stepper, work) = self.stepper();
        work.keep_converged_hessians = linearizing;
        stepper.solve(base, &mu, work, step, time)
    }

    /// The step solver over this integrator's system and settings, beside its workspace.
    pub(super) fn stepper(&mut self) -> (StepSolver<'_, S, C, D>, &mut WorkspaceOf<S, D>) {
        let forcing = self.forcing();
        (
            StepSolver {
                system: &self.system,
                chart: &self.chart,
                settings: &self.settings,
                d: &self.discretisation,
                time: self.state.time,
                forcing,
                point_inputs: self.point_inputs.as_deref(),
            },
            &mut self.work,
        )
    }
}
