"""Type stubs of lgsvi's compiled core (``lgsvi._lgsvi``); the docstrings are the
compiled module's own (``help()`` shows them)."""

from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

Array = NDArray[np.float64]

__version__: str

class LgsviError(Exception): ...
class InvalidInputError(LgsviError, ValueError): ...
class ConvergenceError(LgsviError): ...
class ChartError(LgsviError): ...
class ToleranceError(LgsviError): ...
class ModelError(LgsviError): ...
class InternalError(LgsviError): ...
class InfeasibleError(LgsviError): ...

class System:
    """A mechanical system lgsvi integrates (the base of the built-in systems)."""
    @property
    def inertia(self) -> Array: ...
    @property
    def group(self) -> str: ...
    @property
    def input_dimension(self) -> int: ...
    def __eq__(self, other: object) -> bool: ...

class RigidBody(System):
    def __init__(
        self,
        inertia: Optional[ArrayLike] = None,
        inertia_d: Optional[ArrayLike] = None,
        torque: Optional[ArrayLike] = None,
        damping: float = 0.0,
        attitude_gain: float = 0.0,
        target: Optional[ArrayLike] = None,
    ) -> None: ...

class HeavyTop(System):
    def __init__(
        self,
        inertia: Optional[ArrayLike] = None,
        mass: float = 1.0,
        gravity: float = 9.81,
        com: Optional[ArrayLike] = None,
        gravity_direction: Optional[ArrayLike] = None,
        inertia_d: Optional[ArrayLike] = None,
        torque: Optional[ArrayLike] = None,
        damping: float = 0.0,
        attitude_gain: float = 0.0,
        target: Optional[ArrayLike] = None,
    ) -> None: ...

class FreeBody(System):
    def __init__(
        self,
        inertia: Optional[ArrayLike] = None,
        mass: float = 1.0,
        inertia_d: Optional[ArrayLike] = None,
        torque: Optional[ArrayLike] = None,
        damping: float = 0.0,
        force: Optional[ArrayLike] = None,
        attitude_gain: float = 0.0,
        target: Optional[ArrayLike] = None,
    ) -> None: ...

class OrbitingBody(System):
    def __init__(
        self,
        inertia: Optional[ArrayLike] = None,
        mass: float = 1.0,
        mu: float = 1.0,
        inertia_d: Optional[ArrayLike] = None,
        torque: Optional[ArrayLike] = None,
        damping: float = 0.0,
        force: Optional[ArrayLike] = None,
        attitude_gain: float = 0.0,
        target: Optional[ArrayLike] = None,
    ) -> None: ...

class Gyrostat(System):
    def __init__(self, inertia: ArrayLike, wheel_axes: ArrayLike, wheel_inertias: ArrayLike) -> None: ...

class State:
    @property
    def t(self) -> float: ...
    @property
    def attitude(self) -> Array: ...
    @property
    def quaternion(self) -> Array: ...
    @property
    def omega(self) -> Array: ...
    @property
    def position(self) -> Optional[Array]: ...
    @property
    def velocity(self) -> Optional[Array]: ...
    @property
    def momentum(self) -> Array: ...
    @property
    def spatial_momentum(self) -> Array: ...
    @property
    def linear_momentum(self) -> Optional[Array]: ...
    @property
    def energy(self) -> float: ...
    @property
    def wheel_angles(self) -> Optional[Array]: ...
    @property
    def wheel_speeds(self) -> Optional[Array]: ...
    def to_dict(self) -> Dict[str, Any]: ...

class Curve:
    @property
    def start(self) -> float: ...
    @property
    def h(self) -> float: ...
    def __call__(self, t: float) -> State: ...
    def sample(self, t: ArrayLike) -> Any: ...

class Integrator:
    def __init__(
        self,
        system: System,
        h: float,
        nodes: int = 10,
        attitude: Optional[ArrayLike] = None,
        omega: Optional[ArrayLike] = None,
        position: Optional[ArrayLike] = None,
        velocity: Optional[ArrayLike] = None,
        wheel_speeds: Optional[ArrayLike] = None,
        wheel_angles: Optional[ArrayLike] = None,
        t0: float = 0.0,
        chart: str = "exp",
        matching: str = "exact",
        quadrature_points: Optional[int] = None,
        max_newton_iterations: Optional[int] = None,
    ) -> None: ...
    @property
    def system(self) -> System: ...
    @property
    def state(self) -> State: ...
    @property
    def t(self) -> float: ...
    @property
    def settings(self) -> Dict[str, Any]: ...
    @property
    def stats(self) -> Dict[str, Any]: ...
    @property
    def input(self) -> Array: ...
    def set_input(self, u: ArrayLike) -> None: ...
    def step(self) -> int: ...
    def advance(self, steps: int) -> None: ...
    def run(self, steps: int, every: int = 1) -> Any: ...
    def run_until(
        self,
        t_end: float,
        every: int = 1,
        tol: Optional[float] = None,
        step: Optional[float] = None,
        dense: Optional[ArrayLike] = None,
        events: Optional[Sequence[Any]] = None,
    ) -> Any: ...
    def reset(
        self,
        t0: Optional[float] = None,
        attitude: Optional[ArrayLike] = None,
        omega: Optional[ArrayLike] = None,
        position: Optional[ArrayLike] = None,
        velocity: Optional[ArrayLike] = None,
        wheel_speeds: Optional[ArrayLike] = None,
        wheel_angles: Optional[ArrayLike] = None,
    ) -> None: ...
    def linearize(self, coordinates: str = "velocity", parameters: bool = False, points: bool = False) -> Tuple[Any, ...]: ...
    def step_linearized(self, coordinates: str = "velocity", parameters: bool = False, points: bool = False) -> Tuple[Any, ...]: ...
    def curve(self) -> Optional[Curve]: ...

class Regulator:
    def __init__(self, reference: State, K: ArrayLike, feedforward: Optional[ArrayLike] = None) -> None: ...
    def input(self, state: State) -> Array: ...

def dlqr(A: ArrayLike, B: ArrayLike, Q: ArrayLike, R: ArrayLike) -> Tuple[Array, Array]: ...
def dare(A: ArrayLike, B: ArrayLike, Q: ArrayLike, R: ArrayLike) -> Array: ...
def tvlqr(As: Sequence[ArrayLike], Bs: Sequence[ArrayLike], Q: ArrayLike, R: ArrayLike, Qf: ArrayLike) -> Array: ...
def error_state(state: State, reference: State) -> Array: ...

def gauss_legendre(m: int) -> Tuple[Array, Array]: ...
def gauss_lobatto(m: int) -> Tuple[Array, Array]: ...
def gauss_radau(m: int, side: str = "left") -> Tuple[Array, Array]: ...
def gauss_hermite(m: int) -> Tuple[Array, Array]: ...
def gauss_laguerre(m: int, alpha: float = 0.0) -> Tuple[Array, Array]: ...
def gauss_jacobi(m: int, alpha: float, beta: float) -> Tuple[Array, Array]: ...
def gauss_kronrod(n: int) -> Tuple[Array, Array]: ...
def gauss_kronrod_gauss_weights(n: int) -> Array: ...

class Chebyshev:
    def __init__(self, coefficients: ArrayLike, a: float = -1.0, b: float = 1.0) -> None: ...
    @classmethod
    def fit(cls, f: Callable[[Array], ArrayLike], a: float, b: float, tol: Optional[float] = None) -> "Chebyshev": ...
    @classmethod
    def from_values(cls, values: ArrayLike, a: float = -1.0, b: float = 1.0) -> "Chebyshev": ...
    @property
    def coefficients(self) -> Array: ...
    @property
    def interval(self) -> Tuple[float, float]: ...
    @overload
    def __call__(self, x: float) -> float: ...
    @overload
    def __call__(self, x: ArrayLike) -> Array: ...
    def derivative(self) -> "Chebyshev": ...
    def integral(self) -> "Chebyshev": ...
    def definite_integral(self) -> float: ...
    def roots(self) -> Array: ...
    def range(self) -> Tuple[float, float]: ...
    def __len__(self) -> int: ...
    def __add__(self, other: "Chebyshev") -> "Chebyshev": ...
    def __mul__(self, other: "Chebyshev") -> "Chebyshev": ...

def so3_exp(w: ArrayLike) -> Array: ...
def so3_log(R: ArrayLike) -> Array: ...
def se3_exp(xi: ArrayLike) -> Array: ...
def se3_log(T: ArrayLike) -> Array: ...
def hat(w: ArrayLike) -> Array: ...
def vee(M: ArrayLike) -> Array: ...
def chart_to_group(w: ArrayLike, chart: str = "exp") -> Array: ...
def chart_to_algebra(R: ArrayLike, chart: str = "exp") -> Array: ...
def chart_differential(w: ArrayLike, chart: str = "exp", side: str = "left") -> Array: ...
def quaternion_from_matrix(R: ArrayLike) -> Array: ...
def matrix_from_quaternion(q: ArrayLike) -> Array: ...

def _run_ensemble(
    system: System,
    h: float,
    nodes: int,
    attitudes: ArrayLike,
    omegas: ArrayLike,
    t_end: float,
    positions: Optional[ArrayLike] = None,
    velocities: Optional[ArrayLike] = None,
    wheel_speeds: Optional[ArrayLike] = None,
    chart: str = "exp",
    matching: str = "exact",
    threads: Optional[int] = None,
) -> Dict[str, Any]: ...

class MonteCarloEnvelope:
    @property
    def channels(self) -> List[str]: ...
    @property
    def samples(self) -> int: ...
    @property
    def members(self) -> int: ...
    def merge(self, other: MonteCarloEnvelope) -> None: ...
    def percentile(self, q: float) -> Array: ...

def _montecarlo_chunk(
    system: System,
    attitude: ArrayLike,
    omega: ArrayLike,
    dispersions: str,
    seed: int,
    first: int,
    last: int,
    t_end: float,
    h: float,
    nodes: int,
    samples: int,
    chart: str = "exp",
    matching: str = "exact",
    threads: Optional[int] = None,
    stop_when: Optional[str] = None,
    settle_when: Optional[str] = None,
    position: Optional[ArrayLike] = None,
    velocity: Optional[ArrayLike] = None,
    wheel_speeds: Optional[ArrayLike] = None,
    input: Optional[ArrayLike] = None,
) -> Dict[str, Any]: ...
def _montecarlo_envelope_from_bytes(data: bytes) -> MonteCarloEnvelope: ...

def _slew(
    inertia: ArrayLike,
    t_end: Optional[float],
    attitude_final: ArrayLike,
    attitude0: Optional[ArrayLike] = None,
    omega0: Optional[ArrayLike] = None,
    omega_final: Optional[ArrayLike] = None,
    steps: int = 40,
    nodes: int = 10,
    torque_max: Optional[ArrayLike] = None,
    tolerance: float = 1e-10,
    max_iterations: int = 100,
    warm_start: Optional[ArrayLike] = None,
    cost: str = "energy",
    inputs: str = "constant",
    track: Optional[Tuple[ArrayLike, ArrayLike, Sequence[float]]] = None,
    terminal_cost: Optional[Sequence[float]] = None,
    gravity: Optional[float] = None,
    mass: float = 1.0,
    com: Optional[ArrayLike] = None,
    gravity_direction: Optional[ArrayLike] = None,
    wheels: Optional[ArrayLike] = None,
    wheel_inertia: Optional[ArrayLike] = None,
    wheel_speeds0: Optional[ArrayLike] = None,
    disturbance: Optional[ArrayLike] = None,
) -> Dict[str, Any]: ...

def _manoeuvre(
    inertia: ArrayLike,
    mass: float,
    t_end: Optional[float],
    attitude_final: Optional[ArrayLike] = None,
    position_final: Optional[ArrayLike] = None,
    attitude0: Optional[ArrayLike] = None,
    position0: Optional[ArrayLike] = None,
    omega0: Optional[ArrayLike] = None,
    velocity0: Optional[ArrayLike] = None,
    omega_final: Optional[ArrayLike] = None,
    velocity_final: Optional[ArrayLike] = None,
    mu: Optional[float] = None,
    steps: int = 40,
    nodes: int = 10,
    torque_max: Optional[ArrayLike] = None,
    force_max: Optional[ArrayLike] = None,
    tolerance: float = 1e-10,
    max_iterations: int = 500,
    warm_start: Optional[ArrayLike] = None,
    inputs: str = "constant",
    track: Optional[Tuple[ArrayLike, ArrayLike, ArrayLike, ArrayLike, Sequence[float]]] = None,
    terminal_cost: Optional[Sequence[float]] = None,
    cost: str = "energy",
    disturbance: Optional[ArrayLike] = None,
    disturbance_force: Optional[ArrayLike] = None,
) -> Dict[str, Any]: ...
