#!/usr/bin/env python3
"""Exact collisional moments of the HCS of inelastic hard spheres (d = 3) in the Sonine basis.

Derives, with sympy and no approximation beyond truncating the distribution at a3,

    mu_p = -int dc c^p J*[phi, phi],   phi = phi_M (1 + a2 S2(c^2) + a3 S3(c^2)),   p = 2, 4, 6,

as bilinear forms sum_{k,l in {0,2,3}} a_k a_l M_p[k][l] (a_0 = 1), each entry a polynomial in
lambda = (1 + alpha)/2 times sqrt(2 pi). c = V / sqrt(2T/m), phi_M = pi^(-3/2) exp(-c^2), S_k the
Sonine (associated Laguerre, index 1/2) polynomials, J* the Boltzmann collision operator of paper
000 Eq. (2.5) in these units (unit collision cross-section factor). The HCS conditions are
mu_p = (p/2) zeta* <c^p>, i.e. mu_4 = 5 (1 + a2) mu_2 and mu_6 = (105/4)(1 + 3 a2 - a3) mu_2.

The coefficients printed here are those hard-coded in plugins/diagnostic/hcs_theory (the plugin
is the one place gdsmc evaluates the theory; this script only documents where its numbers come
from). It checks itself against paper 001 Eq. (2.16) (first Sonine a2) and the 3/16 of Eq. (2.14).
Run: /usr/bin/python3 scripts/hcs_sonine_moments.py   (about a minute)
"""
import sympy as sp

X, Y, Z, g, u, lam, al = sp.symbols("X Y Z g u lambda alpha", real=True)
s = sp.sqrt(1 - u**2)


def S(k, x):
    return sp.assoc_laguerre(k, sp.Rational(1, 2), x)


def gauss_moment(n):
    """int_{-inf}^{inf} x^n exp(-2 x^2) dx"""
    if n % 2:
        return 0
    a = n // 2
    return sp.sqrt(sp.pi / 2) * sp.factorial2(2 * a - 1) / sp.Integer(4) ** a if a > 0 else sp.sqrt(sp.pi / 2)


def integrate_C(expr):
    """Gaussian average over C with weight exp(-2 C^2) (unnormalised)."""
    poly = sp.Poly(sp.expand(expr), X, Y, Z)
    out = 0
    for (i, j, k), coeff in poly.terms():
        m = gauss_moment(i) * gauss_moment(j) * gauss_moment(k)
        if m != 0:
            out += coeff * m
    return sp.expand(out)


def moment_matrix(p):
    # c1 = C + g/2, c2 = C - g/2; g along z, sigma = (s, 0, u), x = g.sigma = g u
    C2 = X**2 + Y**2 + Z**2
    A = C2 + g**2 / 4
    B = g * Z
    Cs = s * X + u * Z
    # after the collision: g' = g - 2 lam x sigma, C unchanged
    Bp = g * Z - 2 * lam * g * u * Cs
    gp2 = g**2 - 4 * lam * (1 - lam) * g**2 * u**2
    Ap = C2 + gp2 / 4
    k = p // 2
    before = (A + B) ** k + (A - B) ** k
    after = (Ap + Bp) ** k + (Ap - Bp) ** k
    delta = sp.expand(after - before)
    c1sq = A + B
    c2sq = A - B
    basis = {0: sp.Integer(1), 2: S(2, c1sq), 3: S(3, c1sq)}
    basis2 = {0: sp.Integer(1), 2: S(2, c2sq), 3: S(3, c2sq)}
    M = {}
    for i in (0, 2, 3):
        for j in (0, 2, 3):
            integrand = sp.expand(delta * basis[i] * basis2[j])
            r = integrate_C(integrand)  # polynomial in g, u, s (s only in even powers after C average)
            r = sp.expand(r.subs(s**2, 1 - u**2))
            r = sp.expand(r)
            # sigma: 2 pi int_0^1 du, weight x = g u;  g: 4 pi g^2 exp(-g^2/2) dg
            r = 2 * sp.pi * sp.integrate(sp.expand(r * g * u), (u, 0, 1))
            r = sp.expand(r)
            polyg = sp.Poly(r, g)
            val = 0
            for (n,), cg in polyg.terms():
                # int_0^inf g^(n+2) exp(-g^2/2) dg
                m = n + 2
                val += cg * 4 * sp.pi * sp.Integer(2) ** sp.Rational(m - 1, 2) * sp.gamma(sp.Rational(m + 1, 2))
            # mu_p = -(1/2) pi^-3 int int ... delta
            val = sp.simplify(-sp.Rational(1, 2) * val / sp.pi**3)
            M[(i, j)] = sp.factor(sp.simplify(val / sp.sqrt(2 * sp.pi)))
    return M


def main():
    Ms = {p: moment_matrix(p) for p in (2, 4, 6)}
    for p, M in Ms.items():
        print(f"mu_{p} / sqrt(2 pi), entries M[k][l] (k for particle 1, l for particle 2):")
        for key, v in M.items():
            print(f"  {key}: {sp.expand(v)}")
    # symmetric combinations (the form is symmetric in the two particles)
    a2, a3 = sp.symbols("a2 a3")
    amp = {0: 1, 2: a2, 3: a3}
    mu = {p: sp.expand(sum(amp[i] * amp[j] * M[(i, j)] for (i, j) in M)) for p, M in Ms.items()}
    for p in (2, 4, 6):
        print(f"mu_{p}/sqrt(2pi) =", sp.collect(sp.expand(mu[p].subs(lam, (1 + al) / 2)), [a2, a3]))
    # zeta ratio
    ratio = sp.expand(mu[2] / mu[2].subs({a2: 0, a3: 0}))
    print("zeta*/zeta*_M =", sp.collect(sp.simplify(ratio), [a2, a3]))
    # first Sonine check: linear in a2, a3 = 0
    lin = lambda e: sp.expand(e).subs({a2**2: 0, a3**2: 0}).subs(a2 * a3, 0)
    e1 = sp.expand(mu[4] - 5 * (1 + a2) * mu[2]).subs(a3, 0)
    e1 = sp.expand(e1).coeff(a2, 0) + sp.expand(e1).coeff(a2, 1) * a2
    sol1 = sp.solve(e1.subs(lam, (1 + al) / 2), a2)[0]
    ref = 16 * (1 - al) * (1 - 2 * al**2) / (25 + 72 - al * (57 - 24) - 2 * (1 - al) * al**2)
    print("first Sonine a2 =", sp.factor(sol1), " minus 001 Eq. 2.16:", sp.simplify(sol1 - ref))
    # second Sonine, linear
    e4 = mu[4] - 5 * (1 + a2) * mu[2]
    e6 = mu[6] - sp.Rational(105, 4) * (1 + 3 * a2 - a3) * mu[2]
    def linpart(e):
        e = sp.expand(e)
        return e.coeff(a2, 0).coeff(a3, 0) + e.coeff(a2, 1).coeff(a3, 0) * a2 + e.coeff(a3, 1).coeff(a2, 0) * a3
    L4, L6 = linpart(e4), linpart(e6)
    print("linearised mu4 condition:", sp.collect(sp.expand(L4), [a2, a3]))
    print("linearised mu6 condition:", sp.collect(sp.expand(L6), [a2, a3]))
    sol = sp.solve([L4, L6], [a2, a3], dict=True)[0]
    for alpha in (0.1, 0.3, 0.5, 0.7, 0.9):
        v2 = float(sol[a2].subs(lam, (1 + alpha) / 2))
        v3 = float(sol[a3].subs(lam, (1 + alpha) / 2))
        print(f"alpha = {alpha}: first Sonine a2 = {float(ref.subs(al, alpha)):.5f}; second Sonine (linear) a2 = {v2:.5f}, a3 = {v3:.5f}")


if __name__ == "__main__":
    main()
