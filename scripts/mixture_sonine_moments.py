#!/usr/bin/env python3
"""Collisional moments of a binary mixture of inelastic hard spheres (d = 3) in the first Sonine
approximation, for gdsmc/physics/mixture_theory.hpp.

Species i and j with Maxwellians at a_i = m_i/(2T_i), a_j = m_j/(2T_j), each times
1 + A S_2(a v^2) (S_2(x) = x^2/2 - 5x/2 + 15/8, A = c/2 with Garzo & Dufty's c), collide as smooth
inelastic hard spheres: v1' = v1 - mu_ji (1 + alpha_ij)(g.s) s, mu_ji = m_j/(m_i + m_j). With sympy,
exactly and to first order in A_i, A_j, this derives

    E_p = int dv1 dv2 f_i f_j int ds Theta(g.s)(g.s) (|v1'|^p - |v1|^p),   p = 2, 4,

(per n_i n_j sigma_ij^2), by the change of variables v1 = H + w_j g, v2 = H - w_i g
(w_i = a_i/(a_i + a_j)), under which H and g are independent Gaussians. It prints the reduced
coefficients z = -(2 a_i/3) E_2 / v_ij and w = -(2/15) a_i^2 E_4 / v_ij (v_ij^2 = 1/a_i + 1/a_j) as
functions of w = a_i/(a_i + a_j) and l = (1 + alpha_ij) mu_ji -- the coefficients hard-coded in
mixture_pair_moments -- and checks the header's forms against them, and the one-species limit of the
linearised fourth-moment balances against van Noije & Ernst, Granular Matter 1, 57 (1998):
a2 = 16(1-alpha)(1-2alpha^2)/(81 - 17alpha + 30alpha^2(1-alpha)) in the HCS and
a2 = 16(1-alpha)(1-2alpha^2)/(241 - 177alpha + 30alpha^2(1-alpha)) under white noise.
Run: /usr/bin/python3 scripts/mixture_sonine_moments.py   (about two minutes)
"""
import sympy as sp

X, Y, Z, g, u = sp.symbols("X Y Z g u", real=True)
ai, aj, mu, lam, Ai, Aj = sp.symbols("a_i a_j mu lambda A_i A_j", positive=True)
w, l, al = sp.symbols("w l alpha", positive=True)


def S2(x):
    return x**2 / 2 - sp.Rational(5, 2) * x + sp.Rational(15, 8)


def moments():
    A = ai + aj
    s = sp.sqrt(1 - u**2)
    H = sp.Matrix([X, Y, Z])
    gv = sp.Matrix([0, 0, g])
    sig = sp.Matrix([s, 0, u])  # g along z, u = cos(g, s) > 0
    v1 = H + aj / A * gv
    v2 = H - ai / A * gv
    v1p = v1 - mu * lam * (g * u) * sig
    n1, n2, n1p = (v1.T * v1)[0], (v2.T * v2)[0], (v1p.T * v1p)[0]
    var_h = 1 / (2 * A)  # H ~ exp(-(a_i + a_j) H^2)
    b = ai * aj / A      # g ~ exp(-b g^2)

    def h_moment(n):
        if n % 2:
            return 0
        return sp.factorial2(n - 1) * var_h ** (n // 2) if n else 1

    def g_moment(n):  # <g^n> over 4 pi g^2 (b/pi)^(3/2) exp(-b g^2)
        return sp.gamma(sp.Rational(n + 3, 2)) / sp.gamma(sp.Rational(3, 2)) / b ** sp.Rational(n, 2)

    out = {}
    for p in (2, 4):
        k = p // 2
        e = sp.expand((n1p**k - n1**k) * (1 + Ai * S2(ai * n1) + Aj * S2(aj * n2)))
        poly = sp.Poly(e, X, Y, Z)
        e = sp.expand(sum(c * h_moment(i) * h_moment(j) * h_moment(m) for (i, j, m), c in poly.terms()))
        e = sp.expand(e.subs(s**2, 1 - u**2))
        e = sp.expand(2 * sp.pi * sp.integrate(sp.expand(e * g * u), (u, 0, 1)))
        out[p] = sp.expand(sum(c * g_moment(n) for (n,), c in sp.Poly(e, g).terms()))
    return out


def main():
    E = moments()
    vij = sp.sqrt((ai + aj) / (ai * aj))
    red = {"z": sp.expand(-sp.Rational(2, 3) * ai * E[2] / vij), "w": sp.expand(-sp.Rational(2, 15) * ai**2 * E[4] / vij)}
    sq = sp.sqrt(sp.pi)
    v = 1 - w
    header = {  # mixture_pair_moments
        ("z", 0): 4 * sq / 3 * l * (2 - l / v),
        ("z", 1): sq / 6 * l * v * (6 + 2 * w - 3 * l),
        ("z", 2): -sq / 6 * l * w**2 * (3 * l + 2 * v) / v,
        ("w", 0): 4 * sq / 15 * l * (2 - l / v) * (2 * l**2 - 4 * l * v + v * (6 - w)) / v,
        ("w", 1): -sq / 30 * l * (30 * l**3 + 24 * l**2 * w - 120 * l**2 - 9 * l * w**2 - 69 * l * w + 210 * l
                                  + 6 * w**3 + 16 * w**2 + 78 * w - 180),
        ("w", 2): -sq / 30 * l * w**2 * (30 * l**3 + 24 * l**2 * w - 24 * l**2 - 9 * l * w**2 + 3 * l * w + 6 * l
                                         + 6 * w**3 - 8 * w**2 - 2 * w + 4) / v**2,
    }
    for name, F in red.items():
        for idx, coef in enumerate((F.subs({Ai: 0, Aj: 0}), F.coeff(Ai), F.coeff(Aj))):
            c = sp.factor(sp.simplify(coef.subs(aj, ai * (1 - w) / w).subs(mu, l / lam)))
            diff = sp.simplify(c - header[(name, idx)])
            print(f"{name}[{('0', 'A_i', 'A_j')[idx]}] = {c}   header - derived: {diff}")
            assert diff == 0
    # one species: a_i = a_j, mu = 1/2, A_i = A_j = A; linearised balances
    A = sp.symbols("A")
    one = {ai: 1, aj: 1, mu: sp.Rational(1, 2), lam: 1 + al}
    z = sp.expand(red["z"].subs(one).subs({Ai: A, Aj: A}))
    W = sp.expand(red["w"].subs(one).subs({Ai: A, Aj: A}))
    z0, z1, w0, w1 = z.subs(A, 0), z.coeff(A), W.subs(A, 0), W.coeff(A)
    hcs = sp.solve(w0 + w1 * A - (z0 + z1 * A + z0 * A), A)[0]   # W = zeta (1 + A), linearised
    wn = sp.solve(w0 + w1 * A - (z0 + z1 * A), A)[0]             # W = zeta
    ref_hcs = 16 * (1 - al) * (1 - 2 * al**2) / (81 - 17 * al + 30 * al**2 * (1 - al))
    ref_wn = 16 * (1 - al) * (1 - 2 * al**2) / (241 - 177 * al + 30 * al**2 * (1 - al))
    print("one species, HCS a2 =", sp.factor(hcs), "  minus van Noije & Ernst:", sp.simplify(hcs - ref_hcs))
    print("one species, white noise a2 =", sp.factor(wn), "  minus van Noije & Ernst:", sp.simplify(wn - ref_wn))
    assert sp.simplify(hcs - ref_hcs) == 0 and sp.simplify(wn - ref_wn) == 0


if __name__ == "__main__":
    main()
