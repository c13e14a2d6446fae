"""The 3D pendulum balanced upside down (R = diag(-1, 1, -1), an unstable equilibrium) by an
LQR on the step's exact linearisation, from a tilt of about 6 degrees. Prints the tilt as
it falls; asserts it is below 1e-6 rad after 20 s.

    python python/examples/lqr_upright_pendulum.py
"""

import numpy as np

import lgsvi
from lgsvi import control

top = lgsvi.HeavyTop(inertia_d=[1.0, 2.8, 2.0])  # m = 1, g = 9.81, the centre of mass on e3
upright = np.diag([-1.0, 1.0, -1.0])
h = 0.05

# The exact Jacobians of one step at the equilibrium, in x = (theta, omega).
it = lgsvi.Integrator(top, h, 6, attitude=upright)
A, B = it.linearize()
K, S = control.dlqr(A, B, Q=np.eye(6), R=0.1 * np.eye(3))
regulator = control.Regulator(it.state, K)
reference = it.state

tilt = lgsvi.lie.so3_exp([0.1, 0.05, 0.0])
it.reset(attitude=upright @ tilt)
for k in range(401):
    x = control.error_state(it.state, reference)
    if k % 80 == 0:
        print(f"t = {it.t:5.1f} s  tilt {np.linalg.norm(x[:3]):.2e} rad  |u| "
              f"{np.linalg.norm(regulator.input(it.state)):.2e} N m")
    it.set_input(regulator.input(it.state))
    it.step()
assert np.max(np.abs(control.error_state(it.state, reference))) < 1e-6
