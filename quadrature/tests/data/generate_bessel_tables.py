"""The Bessel tables of the asymptotic Gauss–Legendre rule (quadrature/src/legendre_asymptotic.rs):
the first 20 zeros j_{0,k} of J_0 and J_1(j_{0,k})^2 for k = 1..10, each printed to 20
significant digits from 50-digit mpmath values (the Rust source rounds them to doubles).

    python3 quadrature/tests/data/generate_bessel_tables.py
"""
import mpmath as mp

mp.mp.dps = 50
print("zeros of J_0:")
for k in range(1, 21):
    print(mp.nstr(mp.besseljzero(0, k), 20) + ",")
print("J_1(j_0k)^2:")
for k in range(1, 11):
    print(mp.nstr(mp.besselj(1, mp.besseljzero(0, k)) ** 2, 20) + ",")
