#!/usr/bin/env python3
"""Taylor coefficients and reference values for the `lie` crate, in mpmath at 50 digits.

Independent of the Rust code under test. Prints two blocks:

1. The Taylor coefficients (in s = θ²) of the SO(3) coefficient functions, as correctly
   rounded doubles, pasted into `src/series.rs`:
     sinc      sin θ / θ                      = Σ (−1)^k s^k / (2k+1)!
     one_minus_cos_over_sq (1 − cos θ)/θ²     = Σ (−1)^k s^k / (2k+2)!
     theta_minus_sin_over_cube (θ − sin θ)/θ³ = Σ (−1)^k s^k / (2k+3)!
     jr_inverse  1/θ² − cot(θ/2)/(2θ)         = Σ |B_{2k+2}| s^k / (2k+2)!
   Each is checked here against its closed form at s = 1/4 and s = 4.

2. Reference values written to `reference_values.txt` beside this script: rotation
   matrices of exp, Cayley (standard, ξ/2 scaling) and the paper's unscaled Cayley, and the
   logarithm, at rotation angles 0, 1e-12, 1e-8, 1e-4, 1, π/2, π − 1e-6 and (exp only)
   2π − 1e-3, about a fixed generic axis; plus J_r and J_r⁻¹ at the same angles.
   Lines: `kind angle_label v1 ... vN` (N = 3 or 9, row-major), 25 significant digits.

3. The four coefficient functions and their first derivatives in s, at 2000 doubles s
   spread over (0, 9) (θ evenly in (0, 3)), written to `coefficient_functions.txt` beside
   this script (lines `name s value derivative`, 20 significant digits), for the test that their
   rounding errors average to zero (`series::tests`): a fixed-sign error there breaks the
   integrator's energy behaviour (see `src/series.rs`).

Block 1 also prints, for the first HEAD coefficients of each series, the rounding error
of the double, `c − fl(c)`, as a second double: the series add it back (see `src/series.rs`).

Run: python3 lie/tests/data/generate_reference.py
"""
import os
import mpmath as mp

mp.mp.dps = 50
TERMS = 20
HERE = os.path.dirname(os.path.abspath(__file__))


def series():
    out = {}
    f = mp.factorial
    out["SINC"] = [(-1) ** k / f(2 * k + 1) for k in range(TERMS)]
    out["ONE_MINUS_COS_OVER_SQ"] = [(-1) ** k / f(2 * k + 2) for k in range(TERMS)]
    out["THETA_MINUS_SIN_OVER_CUBE"] = [(-1) ** k / f(2 * k + 3) for k in range(TERMS)]
    out["JR_INVERSE"] = [abs(mp.bernoulli(2 * k + 2)) / f(2 * k + 2) for k in range(TERMS)]
    closed = {
        "SINC": lambda t: mp.sin(t) / t,
        "ONE_MINUS_COS_OVER_SQ": lambda t: (1 - mp.cos(t)) / t**2,
        "THETA_MINUS_SIN_OVER_CUBE": lambda t: (t - mp.sin(t)) / t**3,
        "JR_INVERSE": lambda t: 1 / t**2 - mp.cot(t / 2) / (2 * t),
    }
    for name, coeffs in out.items():
        for s in (mp.mpf(1) / 4, mp.mpf(4)):
            val = mp.fsum(c * s**k for k, c in enumerate(coeffs))
            assert abs(val - closed[name](mp.sqrt(s))) < mp.mpf(10) ** -17 * abs(val), name
    return out


# Terms used below each θ² tier in src/series.rs (TAYLOR_TIERS, JR_INVERSE_TIERS). For
# every series, the remainder of the value and of its first two derivatives in s (what a
# second-order dual number carries through the truncated polynomial),
# Σ_{k≥K} k!/(k−j)! |c_k| s^(k−j) for j = 0, 1, 2, must be ≤ 2^-55 of the same derivative
# of the full function at the tier's upper end; and the explicit derivative series
# (series_derivative, three more terms) likewise. Each tier is also the fewest terms
# that pass (checked below), so it costs nothing it need not.
TAYLOR_TIERS = [(mp.mpf("0.01"), 7), (mp.mpf("0.25"), 9), (mp.mpf(1), 11), (mp.mpf(4), 13)]
JR_INVERSE_TIERS = [(mp.mpf("0.01"), 7), (mp.mpf("0.25"), 11), (mp.mpf(1), 14), (mp.mpf(4), 20)]
TIERS = {
    "SINC": TAYLOR_TIERS,
    "ONE_MINUS_COS_OVER_SQ": TAYLOR_TIERS,
    "THETA_MINUS_SIN_OVER_CUBE": TAYLOR_TIERS,
    "JR_INVERSE": JR_INVERSE_TIERS,
}


def truncation_ok(cs, s, terms):
    bound = mp.mpf(2) ** -55
    for j in range(3):
        falling = lambda k: mp.factorial(k) / mp.factorial(k - j)
        value = mp.fsum(falling(k) * c * s ** (k - j) for k, c in enumerate(cs) if k >= j)
        rem = mp.fsum(falling(k) * abs(c) * s ** (k - j) for k, c in enumerate(cs) if k >= max(terms, j))
        if rem > bound * abs(value):
            return False
    return True


def check_tiers(coeffs):
    # Minimal: with one term fewer, some series sharing the tier table would fail.
    for tiers in (TAYLOR_TIERS, JR_INVERSE_TIERS):
        sharing = [cs for name, cs in coeffs.items() if TIERS[name] is tiers]
        for s, terms in tiers:
            assert any(not truncation_ok(cs, s, terms - 1) for cs in sharing), (s, "not minimal")
    for name, cs in coeffs.items():
        for s, terms in TIERS[name]:
            assert truncation_ok(cs, s, terms), (name, s, terms)
            # The explicit derivative series Σ k c_k s^(k−1) with three more terms.
            d_value = mp.fsum(k * c * s ** (k - 1) for k, c in enumerate(cs) if k >= 1)
            d_rem = mp.fsum(k * abs(c) * s ** (k - 1) for k, c in enumerate(cs) if k >= terms + 3)
            assert d_rem <= mp.mpf(2) ** -55 * abs(d_value), (name, "derivative", s, terms)


# Leading coefficients carried as two doubles in src/series.rs.
HEAD = 3
FUNCTIONS = {
    "sinc": lambda t: mp.sin(t) / t,
    "one_minus_cos_over_sq": lambda t: (1 - mp.cos(t)) / t**2,
    "theta_minus_sin_over_cube": lambda t: (t - mp.sin(t)) / t**3,
    "jr_inverse_coefficient": lambda t: 1 / t**2 - mp.cot(t / 2) / (2 * t),
}
SAMPLES = 2000


def coefficient_functions():
    path = os.path.join(HERE, "coefficient_functions.txt")
    with open(path, "w") as fh:
        fh.write("# name s f(s) f'(s), f in s = θ²; generated by generate_reference.py\n")
        for name, fn in FUNCTIONS.items():
            g = lambda s: fn(mp.sqrt(s))
            for i in range(SAMPLES):
                s = mp.mpf(float((3 * (i + mp.mpf(1) / 2) / SAMPLES) ** 2))
                vals = (g(s), mp.diff(g, s))
                fh.write(f"{name} {float(s)!r} " + " ".join(mp.nstr(v, 20, min_fixed=1, max_fixed=0) for v in vals) + "\n")
    print("// wrote", path)


def hat(w):
    return mp.matrix([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


def expm_so3(w):
    return mp.expm(hat(w))


def cayley_standard(w):
    # (I − ξ̂/2)⁻¹ (I + ξ̂/2)
    i3 = mp.eye(3)
    return mp.inverse(i3 - hat(w) / 2) * (i3 + hat(w) / 2)


def cayley_unscaled(q):
    # (I − q̂)(I + q̂)⁻¹, the paper's chart
    i3 = mp.eye(3)
    return (i3 - hat(q)) * mp.inverse(i3 + hat(q))


def jr(w):
    """Right Jacobian of exp by quadrature of its defining integral ∫_0^1 exp(−s ξ̂) ds."""
    return mp.matrix([[mp.quad(lambda s: mp.expm(-s * hat(w))[i, j], [0, 1]) for j in range(3)] for i in range(3)])


def flat(m):
    return [m[i, j] for i in range(3) for j in range(3)]


def main():
    coeffs = series()
    check_tiers(coeffs)
    for name, tiers in TIERS.items():
        print(f"// {name} tiers checked: " + ", ".join(f"s < {mp.nstr(s, 3)}: {t} terms" for s, t in tiers))
    print("// Generated by tests/data/generate_reference.py (mpmath, 50 digits).")
    for name, cs in coeffs.items():
        print(f"pub(crate) const {name}: [f64; {TERMS}] = [")
        for c in cs:
            # The correctly rounded double, shortest round-trip form.
            print(f"    {float(c)!r},")
        print("];")
        print(f"/// `c_k − fl(c_k)` for the first [`HEAD`] coefficients of [`{name}`].")
        print(f"pub(crate) const {name}_LOW: [f64; HEAD] = [")
        for c in cs[:HEAD]:
            print(f"    {float(c - mp.mpf(float(c)))!r},")
        print("];")

    axis = mp.matrix([mp.mpf(2), mp.mpf(-3), mp.mpf(6)]) / 7  # unit: 4 + 9 + 36 = 49
    angles = [("0", mp.mpf(0)), ("1e-12", mp.mpf("1e-12")), ("1e-8", mp.mpf("1e-8")),
              ("1e-4", mp.mpf("1e-4")), ("1", mp.mpf(1)), ("pi/2", mp.pi / 2),
              ("pi-1e-6", mp.pi - mp.mpf("1e-6")), ("2pi-1e-3", 2 * mp.pi - mp.mpf("1e-3"))]
    lines = []
    for label, th in angles:
        w = axis * th
        lines.append(("exp", label, flat(expm_so3(w))))
        if th > 0:
            lines.append(("jr", label, flat(jr(w))))
            lines.append(("jr_inverse", label, flat(mp.inverse(jr(w)))))
        if label == "2pi-1e-3":
            continue
        # Standard Cayley vector for rotation angle θ: 2 tan(θ/2) n; unscaled: −tan(θ/2) n.
        c = axis * 2 * mp.tan(th / 2)
        lines.append(("cayley_vector", label, list(c)))
        lines.append(("cayley", label, flat(cayley_standard(c))))
        q = axis * (-mp.tan(th / 2))
        lines.append(("cayley_unscaled_vector", label, list(q)))
        lines.append(("cayley_unscaled", label, flat(cayley_unscaled(q))))
        lines.append(("log", label, list(w)))
    path = os.path.join(HERE, "reference_values.txt")
    with open(path, "w") as fh:
        fh.write("# kind angle v... (row-major); axis (2,-3,6)/7; generated by generate_reference.py\n")
        for kind, label, vals in lines:
            fh.write(kind + " " + label + " " + " ".join(mp.nstr(v, 25, min_fixed=1, max_fixed=0) for v in vals) + "\n")
    print("// wrote", path)
    coefficient_functions()


if __name__ == "__main__":
    main()
