"""Shared references for the tests: the repository's 40-digit reference trajectories
(``cases/data``, computed in 63-digit arithmetic by a Taylor series and cross-checked by
extrapolation and, for the free body, the exact elliptic-function solution) and a few
independent helpers built on scipy."""

import json
import pathlib

import numpy as np
import pytest

DATA = pathlib.Path(__file__).resolve().parents[2] / "cases" / "data"


def _load(name):
    with open(DATA / name) as f:
        return json.load(f)


@pytest.fixture(scope="session")
def so3_refs():
    """The free body (A) and heavy top (B, C) references, case by name."""
    return _load("rigid_body_refs.json")["cases"]


@pytest.fixture(scope="session")
def se3_refs():
    """The full tensor (FJ1), torqued (F1) and orbiting (O1) references."""
    return _load("se3_forced_refs.json")["cases"]


def numbers(values):
    """Decimal strings as floats (the nearest double)."""
    return np.array([float(v) for v in values])


def reference_state(case, t):
    """The reference state at time ``t`` (one of the stored output times)."""
    for state in case["states"]:
        if float(state["t"]) == t:
            return state
    raise KeyError(t)


def attitude_error(r, r_ref):
    """The largest entry of ``R - R_ref``."""
    return float(np.max(np.abs(np.asarray(r) - np.asarray(r_ref))))
