"""Control design on a step's exact linearisation, and a sampled PD attitude law.

``A, B = integrator.linearize()`` gives the step's exact Jacobians in the coordinates
``x = (theta, omega)``: the attitude (and a body in space's position) perturbed in the
body frame, ``R = Rbar expm(hat(theta))``, and the body velocity by ``xi = xibar + omega``.
:func:`dlqr` designs the gain of ``u = -K x`` (Drake's order and sign), :func:`tvlqr` the
gains along a trajectory, :func:`error_state` the ``x`` of a state against a reference, and
:class:`Regulator` closes the loop: ``integrator.set_input(regulator.input(state))``.

:class:`PdLaw` is the PD attitude law ``u = -K theta - C omega`` with an actuator's torque
limit, for a controller that samples the state and holds its torque:
``integrator.set_input(law.input(state))`` at each sample, or
``lgsvi.montecarlo.run(..., controller=law, sample_period=T)`` for dispersed runs.
"""

from ._lgsvi import PdLaw, Regulator, dare, dlqr, error_state, tvlqr

__all__ = ["PdLaw", "Regulator", "dare", "dlqr", "error_state", "tvlqr"]
