#!/usr/bin/python3
"""Linearized-BGK reference for the flow rate of acceleration-driven plane Poiseuille flow of an
ELASTIC hard-sphere gas between two fully diffuse walls at rest (paper 004, Gupta & Alam, PRE 95,
022903 (2017), Eqs. 17, 18, 40), small-acceleration (linear) regime.  numpy only.

Usage: poiseuille_reference.py --kn 0.02 0.05 0.1 [--json FILE] [--selftest]
Import: flow_rate(kn) -> (Q, y, U),  y in [-1/2, 1/2] (units of W),  U = u_x/(v0 a_hat).

Conventions. Walls at y = +-W/2, acceleration a along x, v0 = sqrt(2kT_w/m), a_hat = aW/v0^2,
Kn = lambda/W with lambda = 1/(sqrt(2) pi n d^2), Q = int rho u_x dy/(rho_av v0 W a_hat) (Eq. 40).
Model: BGK with nu = p/eta_HS, eta_HS = 1.016034 (5/16) sqrt(mkT/pi)/d^2 (Chapman-Enskog), so the
rarefaction parameter is delta = nu W/v0 = pW/(eta v0) = DELTA_KN/Kn, DELTA_KN = 8/(5 sqrt(pi)
1.016034) = 0.888458.  This delta and Q are exactly Sharipov's delta and reduced flow rate G_P
(body force a <-> -(1/rho) dp/dx), so tables of G_P(delta) compare directly: Q(Kn) = G_P(DELTA_KN/Kn).

Derivation. Linearize f = f_M(c)[1 + 2 c_x a_hat w(y, c_y)], c = v/v0, y in units of W: this is a
Maxwellian shifted by a_hat w v0 along x.  Integrating out c_x, c_z of the BGK equation leaves
    c_y dw/dy = 1 + delta (U - w),  U(y) = pi^-1/2 int w e^{-c_y^2} dc_y,  u_x/v0 = a_hat U,
with w = 0 for molecules leaving a wall.  Along characteristics this gives the integral equation
    U(y) = pi^-1/2 int_{-1/2}^{1/2} T_{-1}(delta|y - y'|) [1 + delta U(y')] dy',
T_n(x) = int_0^inf c^n exp(-c^2 - x/c) dc (Abramowitz), and Q = int U dy.
Independent checks of the factors: (i) kinematics: a molecule leaving a wall with c_y reaches
distance s having gained Delta v_x = a s W/(c_y v0), i.e. w = s/c_y, which is the delta = 0 solution
(source term exactly 1, U = density-weighted mean of w);  (ii) Navier-Stokes u = rho a (W^2/4 -
y^2)/(2 eta) gives Q = rho v0 W/(12 eta) = delta/6, since delta = rho v0 W/(2 eta).
Limits (both verified by --selftest):
  continuum   delta >> 1:  Q = delta/6 + sigma_P + O(1/delta), BGK viscous-slip coefficient
              sigma_P = 1.016191 (slip length sigma_P eta v0/p); the fit of the solver gives it.
  free-molec. delta << 1:  Q = [ln(1/delta) + 3(1 - gamma_E)/2]/sqrt(pi) + (delta/pi) ln^2 delta
              + ...  (derived here from T_{-1}(x) = -ln x - 3 gamma_E/2 + o(1)).
HS versus BGK (same Kn, same viscosity): the continuum terms delta/6 agree, the O(1) slip constants
differ (sigma_P(HS) - sigma_P(BGK)).  As Kn -> inf the log coefficients agree and the constants
differ by the loss-term cut-off: Q_HS - Q_BGK -> -<ln(nu_HS(c)/nu_BGK)>/sqrt(pi) = hs_fm_offset()
(= -0.170, average over c_y = 0 molecules with weight 2 c_x^2 e^{-c^2}/pi; the HS collision rate of
the fast grazing molecules that carry the log exceeds p/eta).  So at large Kn Q_BGK should exceed
DSMC's HS value, by an amount approaching 0.170 (8 % of Q at Kn = 10; at finite Kn the
O(delta ln^2 delta) terms differ too, so this is an estimate).  At small Kn the difference tends to
the slip-coefficient difference (HS value not retrieved here), relatively small since Q ~ delta/6.

Numerics: Nystrom product integration, U piecewise linear on a uniform grid of N cells (kernel
integrated exactly with T_0, T_1), symmetric fold, dense solve; Richardson extrapolation of the
N and 2N solutions (error ~ h^2 ln h from the wall singularity U ~ s ln s).  N = max(800, 40 delta).
Reported err = |R(N, 2N) - R(N/2, N)| (conservative).  Agrees with CROSS_CHECK_BGK's full 121-node
table to < 2e-6 relative for 1e-5 <= delta <= 60; no velocity grid (c_y integrals are analytic).
"""
import os
for _v in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")  # one core: the machine is shared
import argparse
import json
import math
import sys

import numpy as np

SQPI = math.sqrt(math.pi)
ETA_HS_CE = 1.016034                           # Chapman-Enskog HS viscosity factor
DELTA_KN = 8.0 / (5.0 * SQPI * ETA_HS_CE)      # delta = DELTA_KN / Kn = 0.888458.../Kn
SIGMA_P_BGK = 1.016191                         # BGK viscous slip coefficient (see CROSS_CHECK_BGK)
FM_CONST = 1.5 * (1.0 - 0.5772156649015329) / SQPI   # 3(1-gamma_E)/(2 sqrt(pi)) = 0.357796

# Reference values found with the available (offline) search tools.  No PUBLISHED table of the plane
# channel flow rate (Ohwada-Sone-Aoki 1989 HS, Sharipov-Seleznev 1998, Cercignani-Daneri 1963,
# Loyalka et al., Siewert 2003) was retrievable: only abstracts/first pages are stored.  What was
# found is an independent linearized-BGK table (Sharipov's G_P(delta), same delta as here) carried in
# a public GitHub Julia file (MEMS squeeze-film model; read via the code index, file id 70109149407;
# its comment: "validated against Barichello et al. 2001 to seven digits"; slip tail
# delta/6 + 1.016191 + 1.0650/delta - 2.1246/delta^2).  It is NOT a peer-reviewed source; it is used
# only to check this solver.  Entries: delta -> G_P (= Q).  Nodes: 10**(log10(1e-5) + k*log10(6e6)/120).
CROSS_CHECK_BGK = {
    1.0e-5: 6.853741530642733, 1.0242504336003874e-1: 2.0241403039436197,
    0.3301927248894628: 1.6806372556853115, 1.0644587690012692: 1.538087688900252,
    3.431548866750505: 1.7673533428030044, 11.062455369638311: 2.9391323933134523,
    60.0: 11.033360902484304,
}


def abramowitz(n, x):
    """T_n(x) = int_0^inf c^n exp(-c^2 - x/c) dc, x >= 0, by the trapezoid rule in s = ln c
    (integrand analytic and decaying both ways: error ~1e-16 relative)."""
    h = 0.05
    s = -40.0 + h * np.arange(int(44.0 / h) + 1)
    c = np.exp(s)
    x = np.asarray(x, float).ravel()
    out = np.empty(x.size)
    for k in range(0, x.size, 512):
        out[k:k + 512] = np.exp((n + 1) * s - c * c - x[k:k + 512, None] / c).sum(axis=1) * h
    return out


def _solve(delta, N):
    """Piecewise-linear Nystrom solution on N uniform cells (N even): (Q, U at the N+1 nodes)."""
    h = 1.0 / N
    t = h * np.arange(N + 2)
    T0, T1 = abramowitz(0, delta * t), abramowitz(1, delta * t)
    F0 = (0.5 * SQPI - T0) / delta                         # int_0^t T_{-1}(delta s) ds
    F1 = (0.5 - T1) / delta**2 - t * T0 / delta            # int_0^t s T_{-1}(delta s) ds
    m = np.arange(N + 1)
    I0 = F0[m + 1] - F0[m]                                 # cell [mh, (m+1)h]: total weight
    I1 = (F1[m + 1] - F1[m]) / h - m * I0                  # ... weight of the far node
    near = I0 - I1
    g = np.empty(N + 1)
    g[0], g[1:] = 2.0 * near[0], I1[:N] + near[1:]
    M = N // 2
    i = np.arange(M + 1)
    A = g[np.abs(i[:, None] - np.arange(N + 1)[None, :])]
    A[:, N] -= near[N - i]                                 # no cell beyond the walls
    A[:, 0] -= near[i]
    A /= SQPI
    b = A.sum(axis=1)
    B = A[:, :M + 1].copy()
    B[:, :M] += A[:, N:M:-1]                               # fold: U(y) = U(-y)
    Uh = np.linalg.solve(np.eye(M + 1) - delta * B, b)
    U = np.concatenate([Uh, Uh[-2::-1]])
    return h * (U.sum() - 0.5 * (U[0] + U[-1])), U


def flow_rate_delta(delta, N=None):
    """(Q, y, U, err) at rarefaction parameter delta; Richardson-extrapolated N/2N solution."""
    if N is None:
        N = 100 * math.ceil(max(800.0, 40.0 * delta) / 100.0)
    qa, ua = _solve(delta, N // 2)
    qb, ub = _solve(delta, N)
    qc, uc = _solve(delta, 2 * N)
    rb, rc = (4 * qb - qa) / 3, (4 * qc - qb) / 3
    U = (4 * uc[::2] - ub) / 3
    return rc, np.linspace(-0.5, 0.5, N + 1), U, abs(rc - rb)


def flow_rate(kn):
    """Linearized-BGK flow rate Q (Eq. 40) at Knudsen number kn, and the profile u_x/(v0 a_hat)."""
    Q, y, U, _ = flow_rate_delta(DELTA_KN / kn)
    return Q, y, U


def q_continuum(delta):
    return delta / 6.0 + SIGMA_P_BGK


def q_free_molecular(delta):
    return (math.log(1.0 / delta)) / SQPI + FM_CONST + delta / math.pi * math.log(delta)**2


def hs_fm_offset():
    """lim_{Kn->inf} (Q_HS - Q_BGK) = -<ln(nu_HS(c)/nu_BGK)>/sqrt(pi), weight 2c^3 e^{-c^2} dc
    (the c_y = 0 molecules, weight 2 c_x^2 e^{-c^2}/pi, in polar form).  nu_HS(c)/nu_BGK =
    1.016034 (5/16) sqrt(2 pi) [e^{-c^2}/sqrt(pi) + (c + 1/(2c)) erf(c)]."""
    c = np.linspace(1e-6, 12.0, 120001)
    nuh = np.exp(-c * c) / SQPI + (c + 0.5 / c) * np.array([math.erf(v) for v in c])
    f = 2 * c**3 * np.exp(-c * c) * np.log(ETA_HS_CE * 5 / 16 * math.sqrt(2 * math.pi) * nuh)
    return -np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(c)) / SQPI


def selftest():
    ok = True
    def report(name, good, text):
        nonlocal ok
        ok &= bool(good)
        print("%-5s %-34s %s" % ("ok" if good else "FAIL", name, text))
    for d, ref in sorted(CROSS_CHECK_BGK.items()):
        q, _, _, e = flow_rate_delta(d)
        report("cross-check delta=%.4g" % d, abs(q / ref - 1) < 1e-5,
               "Q=%.9f ref=%.9f rel=%.1e est.err=%.1e" % (q, ref, q / ref - 1, e))
    for d in (1e-4, 1e-6):
        q = flow_rate_delta(d)[0]
        report("free-molecular delta=%g" % d,
               abs(q - q_free_molecular(d)) < 0.5 * d * math.log(d)**2 / math.pi,
               "Q=%.6f asymptote=%.6f" % (q, q_free_molecular(d)))
    ds = (20.0, 40.0, 80.0)
    r = [flow_rate_delta(d)[0] - d / 6 for d in ds]
    sig = np.linalg.solve([[1, 1 / d, 1 / d**2] for d in ds], r)[0]
    report("continuum: fitted sigma_P", abs(sig - SIGMA_P_BGK) < 1e-3,
           "sigma_P=%.5f (Q-delta/6 = %s)" % (sig, ", ".join("%.5f" % v for v in r)))
    print("HS-BGK free-molecular offset: %.5f" % hs_fm_offset())
    return ok


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--kn", type=float, nargs="+", default=[0.02, 0.05, 0.1, 0.2, 0.5, 1, 2, 5, 10])
    ap.add_argument("--json", help="write Kn, delta, Q, err and profiles to this file")
    ap.add_argument("--selftest", action="store_true", help="check limits and the BGK cross-check")
    a = ap.parse_args(argv)
    if a.selftest:
        return 0 if selftest() else 1
    out = {"Kn": [], "delta": [], "Q": [], "Q_err": [], "profiles": {},
           "model": "linearized BGK, nu = p/eta_HS, diffuse walls; Q as Eq. 40 of paper 004",
           "profile_units": "y/W, u_x/(v0 a_hat)"}
    print("%8s %10s %12s %9s %12s %12s" % ("Kn", "delta", "Q_BGK", "est.err", "d/6+sig_P", "free-mol"))
    for kn in a.kn:
        d = DELTA_KN / kn
        Q, y, U, err = flow_rate_delta(d)
        fm = "%12.5f" % q_free_molecular(d) if d <= 0.1 else "%12s" % "-"
        print("%8g %10.5f %12.7f %9.1e %12.5f %s" % (kn, d, Q, err, q_continuum(d), fm))
        step = (len(y) - 1) // 100
        out["Kn"].append(kn); out["delta"].append(d); out["Q"].append(Q); out["Q_err"].append(err)
        out["profiles"]["%g" % kn] = {"y": [round(v, 6) for v in y[::step]],
                                      "u": [float("%.8g" % v) for v in U[::step]]}
    if a.json:
        with open(a.json, "w") as f:
            json.dump(out, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
