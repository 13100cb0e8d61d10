#!/usr/bin/python3
"""Turn the HDF5 files of scripts/validate-heat-flux into docs/validation/heat-flux.md: paper 001's
modified thermal conductivity kappa', the Sonine coefficients b'_k, the distribution phi(c_x^2)
and beta1 (Figs. 1-7), and kappa itself from the steady Eq. 3.17 and from the time route, beside
the first-Sonine theory (Eqs. 2.14, 2.16, 2.41, 2.42, 2.46) and the converged elastic value.

Usage: heat_flux_report.py DIR > docs/validation/heat-flux.md
DIR holds heat_flux_sweep.h5, heat_flux_kappa_sweep.h5, heat_flux_eps005.h5,
heat_flux_time_route.h5 and NAME.seconds / NAME.log for each run.
Needs Debian's python3-h5py and python3-numpy."""
import os
import sys

import h5py
import numpy as np

ELASTIC_KAPPA = 1.025218  # converged Sonine kappa/kappa0 at alpha = 1 (001, ref. 37)
PAPER_BETA6 = {1.0: 0.87, 0.3: 0.66}  # 001 Sec. IV: share of b'_1 carried by c_x^2 <= 6


def weighted_fit(A, y, e):
    """Weighted least squares y ~ A c with standard errors e: (coefficients, covariance, chi^2)."""
    W = np.diag(1 / e ** 2)
    cov = np.linalg.inv(A.T @ W @ A)
    c = cov @ A.T @ W @ y
    return c, cov, float(np.sum(((A @ c - y) / e) ** 2))


def sonine(alpha):
    """First Sonine, d = 3: a2 (2.16), zeta0/nu0 (2.14), nu_kappa/nu0 (2.46), kappa'/kappa0 (2.42),
    kappa/kappa0 (2.41), both over kappa0 of 2.47."""
    a = alpha
    a2 = 16 * (1 - a) * (1 - 2 * a * a) / (25 + 24 * 3 - a * (57 - 8 * 3) - 2 * (1 - a) * a * a)
    zeta = 5 / 12 * (1 - a * a) * (1 + 3 * a2 / 16)
    nu = (1 + a) / 3 * (1 + 33 / 16 * (1 - a) + (19 - 3 * a) / 512 * a2)
    kp = 2 / 3 * (1 + 1.5 * a2) / (nu - 1.5 * zeta)
    k = 2 / 3 * (1 + 2 * a2) / (nu - 2 * zeta)
    return a2, zeta, nu, kp, k


NU0_TAU0 = 8 / (5 * np.sqrt(np.pi))  # nu0 tau0 at T0 (Eq. 2.15 with lambda0 = 1/(sqrt2 pi n sigma^2))


def fmt(m, e=float("nan"), digits=3):
    if m is None or not np.isfinite(m):
        return "n/a"
    if e is None or not np.isfinite(e):
        return f"{m:.{digits}f}"
    return f"{m:.{digits}f} ± {e:.{digits}f}"


def seconds(d, name):
    p = os.path.join(d, name + ".seconds")
    return float(open(p).read()) if os.path.exists(p) else float("nan")


class Case:
    def __init__(self, group, summary_row=None):
        self.g = group
        self.d = group["diagnostics/heat_flux"]
        self.alpha = float(self.d["restitution"][()])

    def steady(self, name):
        return float(self.d[name + ".steady_mean"][()]), float(self.d[name + ".steady_stderr"][()])

    def series(self, name):
        return np.array(self.d[name][:]), (np.array(self.d[name + "_stderr"][:]) if name + "_stderr" in self.d else None)

    def time(self):
        return np.array(self.d["time"][:])

    def scalar(self, name):
        return float(self.d[name][()]), (float(self.d[name + "_stderr"][()]) if name + "_stderr" in self.d else float("nan"))

    def array(self, name):
        """A dataset, or a histogram's values (a group with edges and values), and its error."""
        def values(o):
            return np.array(o["values"][:]) if isinstance(o, h5py.Group) else np.array(o[:])
        err = self.d.get(name + "_stderr")
        return values(self.d[name]), (values(err) if err is not None else None)

    def edges(self, name):
        return np.array(self.d[name]["edges"][:])

    def run_attr(self, name):
        return float(self.g["run"].attrs[name])


def cases(f):
    if "cases" in f:
        return [Case(f["cases"][k]) for k in sorted(f["cases"].keys(), key=int)]
    return [Case(f)]


def at_times(t, y, e, wanted):
    rows = []
    for w in wanted:
        k = int(np.argmin(np.abs(t - w)))
        rows.append((t[k], y[k], e[k] if e is not None else float("nan")))
    return rows


def time_route_kappa(case, zeta_tau0, t_cut):
    """kappa/kappa0 = sum_k exp(zeta t_k/2) [K(t_k) - K(t_{k-1})], K(0) = 0, up to t_cut, per
    realization; mean and standard error over the realizations."""
    reals = case.d["realizations"]
    values = []
    for r in sorted(reals.keys(), key=int):
        K = np.array(reals[r]["conductivity_over_kappa0"][:])
        t = case.time()
        keep = (t > 0) & (t <= t_cut)
        Kk, tk = K[keep], t[keep]
        dK = np.diff(np.concatenate([[0.0], Kk]))
        tm = 0.5 * (tk + np.concatenate([[0.0], tk[:-1]]))  # the interval over which K changed
        values.append(float(np.sum(np.exp(0.5 * zeta_tau0 * tm) * dK)))
    v = np.array(values)
    return v.mean(), v.std(ddof=1) / np.sqrt(len(v)), len(v)


def main():
    d = sys.argv[1]
    out = []
    w = out.append
    fp = h5py.File(os.path.join(d, "heat_flux_sweep.h5"))
    fk = h5py.File(os.path.join(d, "heat_flux_kappa_sweep.h5"))
    fl = h5py.File(os.path.join(d, "heat_flux_eps005.h5"))
    ft = h5py.File(os.path.join(d, "heat_flux_time_route.h5"))
    cp, ck, cl, ct = cases(fp), cases(fk), cases(fl)[0], cases(ft)
    K = int(fp.attrs["realizations"])
    Kk = int(fk.attrs["realizations"])
    Kt = int(ft.attrs["realizations"])
    N = int(cp[0].g["system"].attrs["particles"]) if "particles" in cp[0].g["system"].attrs else 200000
    sec = {n: seconds(d, n) for n in ("kappa_prime", "kappa", "linearity", "time_route")}

    w("# Validation: thermal conductivity of the granular gas by a homogeneous heat-flux force (paper 001)")
    w("")
    w("Generated by `scripts/validate-heat-flux` (`scripts/heat_flux_report.py`); do not edit by hand.")
    w("")
    w("Paper 001 (Montanero, Santos, Garzó) drives the homogeneous cooling state of inelastic hard spheres with")
    w("a weak velocity-dependent force F′_ε = G′(V)·ε (Eqs. 3.2, 2.32) and the thermostat of Eq. 4.2, and measures")
    w("the modified thermal conductivity κ′ = −q_x/(Tε) (Eq. 3.9), the Sonine coefficients b′_k (Eqs. 3.10, 3.12)")
    w("and the first-order distribution (Eqs. 3.15, 4.3–4.6). gdsmc runs it with `heat_flux_force`,")
    w("`energy_momentum_thermostat` and the `heat_flux` diagnostic, and goes beyond the paper: κ itself from")
    w("the steady Eq. 3.17 with the cloning–annihilation term (`cloning_annihilation`, derivation in")
    w("`docs/heat-flux-kappa.md`), checked against an independent time route.")
    w("")
    w("## Protocol and cost")
    w("")
    w(f"As the paper: N = {N}, δt = 0.003τ (τ = λ/v₀ = τ⁰: the thermostat holds T = T₀), initial Gaussian,")
    w("ε* = λε = 0.025 (0.05 for the linearity check), ε along x. Averages over t ∈ [10, 25]τ (the paper: steady")
    w(f"after about ten collisions per particle), {K} realizations per α for κ′ and {Kk} for κ (the paper used 200")
    w("realizations; we average each over 15τ ≈ 17 collision times instead, and the errors below are the")
    w(f"standard errors of the realization means, Student t with {K - 1} degrees of freedom for κ′).")
    w("")
    w("| run | cases × realizations | wall time | per realization | collisions/s | particle steps/s |")
    w("|---|---|---|---|---|---|")
    for name, f, cs, label in (("kappa_prime", fp, cp, "κ′ sweep (`heat_flux_sweep.yaml`)"),
                               ("kappa", fk, ck, "κ sweep (`heat_flux_kappa_sweep.yaml`)"),
                               ("linearity", fl, [cl], "α = 0.3, ε* = 0.05"),
                               ("time_route", ft, ct, "time route, α = 0.9–0.7")):
        R = int(f.attrs["realizations"])
        s = sec[name]
        coll = sum(c.run_attr("collisions") for c in cs) * R  # realization 0's count, times R
        steps = sum(c.run_attr("steps") for c in cs) * R
        w(f"| {label} | {len(cs)} × {R} | {s:.0f} s | {s / (len(cs) * R):.1f} s | {coll / s:.3g} | {steps * N / s:.3g} |")
    w("")
    w("Both sweeps ran at the same time, one per core. At δt = 0.003τ a particle collides once per ~300 steps,")
    w("so the cost is the per-step passes over all particles (force, thermostat, the diagnostic every 10 steps),")
    w("not collisions: the collision rate above is far below the bare IHS collision stage of `gdsmc_bench`")
    w("(`BM_PluginCollideCell`: 7.6·10⁶ collisions/s at N = 10⁵, 2.3·10⁶ at 10⁶ on this machine, issue 13), and the")
    w("particle-step rate is the figure of merit. The κ route adds the HCS reservoir and the nearest-neighbour")
    w("annihilation (a velocity grid rebuilt every step).")
    w("")

    # Fig. 3
    w("## Fig. 3: κ′/κ₀ against α")
    w("")
    w("| α | κ′/κ₀ (DSMC) | first Sonine (2.42) | DSMC − Sonine |")
    w("|---|---|---|---|")
    anchor = None
    for c in cp:
        k, e = c.steady("conductivity_over_kappa0")
        th = sonine(c.alpha)[3]
        w(f"| {c.alpha:.1f} | {fmt(k, e)} | {th:.3f} | {k - th:+.3f} |")
        if abs(c.alpha - 1) < 1e-9:
            anchor = (k, e)
    w("")
    if anchor:
        k, e = anchor
        z = (k - ELASTIC_KAPPA) / e
        w(f"**The paper's anchor.** At α = 1, κ′ = κ and the converged Sonine value is κ/κ₀ = {ELASTIC_KAPPA}. "
          f"gdsmc: {fmt(k, e, 4)}, {z:+.1f} standard errors from it; the first-Sonine value 1 is "
          f"{(k - 1) / e:+.1f} errors away.")
        w("")

    # The anchor against eps*
    anchor_path = os.path.join(d, "heat_flux_anchor.h5")
    if os.path.exists(anchor_path):
        fa = h5py.File(anchor_path)
        ca = cases(fa)
        Ka = int(fa.attrs["realizations"])
        eps = np.array([float(c.scalar("epsilon_star")[0]) for c in ca])
        kv = np.array([c.steady("conductivity_over_kappa0")[0] for c in ca])
        ke = np.array([c.steady("conductivity_over_kappa0")[1] for c in ca])
        # q_x is odd in eps: kappa(eps) = kappa(0) + c eps^2 + O(eps^4); weighted least squares.
        coef, cov, chi2 = weighted_fit(np.vstack([np.ones_like(eps), eps ** 2]).T, kv, ke)
        w("**The anchor against the field strength.** Linear response is the limit ε* → 0 (Eq. 3.9), and q_x")
        w(f"is odd in ε*, so κ′(ε*) = κ′(0) + c ε*² + O(ε*⁴). At α = 1, δt = 0.03τ, {Ka} realizations per ε*:")
        w("")
        w("| ε* | κ′/κ₀ |")
        w("|---|---|")
        for e_, k_, ke_ in zip(eps, kv, ke):
            w(f"| {e_:g} | {fmt(k_, ke_, 4)} |")
        w("")
        k0, k0e = coef[0], np.sqrt(cov[0, 0])
        w(f"Weighted fit: κ′(0)/κ₀ = {fmt(k0, k0e, 4)} ({(k0 - ELASTIC_KAPPA) / k0e:+.1f} errors from {ELASTIC_KAPPA}), "
          f"c = {coef[1]:.2f} ± {np.sqrt(cov[1, 1]):.2f}, χ² = {chi2:.1f} for {len(eps) - 2} degrees of freedom.")
        w("")

    # Fig. 4
    w("## Fig. 4: b′_k against α (Eq. 3.10; Eq. 3.12 beside it)")
    w("")
    w("| α | b′₁ (3.10) | b′₁ (3.12) | b′₂ (3.10) | b′₂ (3.12) | b′₃ (3.10) | b′₃ (3.12) | first-Sonine b′₁ |")
    w("|---|---|---|---|---|---|---|---|")
    for c in cp:
        row = [f"{c.alpha:.1f}"]
        for k in (1, 2, 3):
            for m in ("full", "marginal"):
                row.append(fmt(*c.steady(f"b{k}_{m}")))
        row.append(f"{15 * np.sqrt(np.pi) / 16 * sonine(c.alpha)[3]:.3f}")
        w("| " + " | ".join(row) + " |")
    w("")
    w("Eq. 3.10 and Eq. 3.12 estimate the same coefficient from the same particles (the paper's Appendix, in the")
    w("linear regime). b′₁ and b′₂ agree within their errors at every α; b′₃ by Eq. 3.12 lies above Eq. 3.10 by")
    w("0.01–0.06 (up to about 3 errors) at most α — the paper saw the two distinguishable only for b′₃ at α = 0.3.")
    w("L₃^(1/2)(c_x²) weights c_x⁷, so this moment is the most sensitive to the O(ε*³) response and to the tail;")
    w("not investigated further.")
    w("")

    # Fig. 1
    w("## Fig. 1: κ′(t)/κ₀ at α = 0.3 for ε* = 0.025 and 0.05")
    w("")
    c03 = [c for c in cp if abs(c.alpha - 0.3) < 1e-9][0]
    t1, y1, e1 = c03.time(), *c03.series("conductivity_over_kappa0")
    t2, y2, e2 = cl.time(), *cl.series("conductivity_over_kappa0")
    wanted = [1, 2, 3, 4, 6, 8, 10, 12, 15, 20, 25]
    w("| t/τ | ε* = 0.025 | ε* = 0.05 |")
    w("|---|---|---|")
    for (ta, ya, ea), (tb, yb, eb) in zip(at_times(t1, y1, e1, wanted), at_times(t2, y2, e2, wanted)):
        w(f"| {ta:.1f} | {fmt(ya, ea)} | {fmt(yb, eb)} |")
    ka, ea_ = c03.steady("conductivity_over_kappa0")
    kb, eb_ = cl.steady("conductivity_over_kappa0")
    w(f"| steady | {fmt(ka, ea_)} | {fmt(kb, eb_)} |")
    w("")
    w(f"Steady difference (0.05 − 0.025): {kb - ka:+.3f} ± {np.hypot(ea_, eb_):.3f}: q_x is linear in ε* within the errors"
      if abs(kb - ka) < 3 * np.hypot(ea_, eb_) else
      f"Steady difference (0.05 − 0.025): {kb - ka:+.3f} ± {np.hypot(ea_, eb_):.3f}: **more than 3 errors** (finding below).")
    w("")

    # Fig. 2
    w("## Fig. 2: b′_k(t) at α = 1 and α = 0.3, by Eq. 3.10 (full) and Eq. 3.12 (marginal)")
    w("")
    for alpha in (1.0, 0.3):
        c = [c for c in cp if abs(c.alpha - alpha) < 1e-9][0]
        t = c.time()
        w(f"α = {alpha}:")
        w("")
        w("| t/τ | b′₁ full | b′₁ marginal | b′₂ full | b′₂ marginal | b′₃ full | b′₃ marginal |")
        w("|---|---|---|---|---|---|---|")
        cols = [c.series(f"b{k}_{m}") for k in (1, 2, 3) for m in ("full", "marginal")]
        for wt in [1, 2, 4, 6, 8, 10, 15, 20, 25]:
            k = int(np.argmin(np.abs(t - wt)))
            w(f"| {t[k]:.1f} | " + " | ".join(fmt(y[k], e[k] if e is not None else float('nan'), 2) for y, e in cols) + " |")
        w("")

    # Figs. 5-6
    w("## Figs. 5–6: φ(c_x²) with the truncated Sonine series φ₁, φ₂, φ₃ (Eqs. 4.3–4.5)")
    w("")
    w("φ from g⁽¹⁾ = [g(c_x) − g(−c_x)]/2 of the steady window (Eq. 3.15), bin width 0.1 in c_x; the error is")
    w("that of the realizations. φ_p uses the measured b′_k (Eq. 3.10).")
    w("")
    for alpha in (1.0, 0.9, 0.7, 0.5, 0.3):
        c = [c for c in cp if abs(c.alpha - alpha) < 1e-9][0]
        phi, phe = c.array("phi")
        p1, _ = c.array("phi_1")
        p2, _ = c.array("phi_2")
        p3, _ = c.array("phi_3")
        edges = c.edges("phi")
        centres = 0.5 * (edges[1:] + edges[:-1])
        w(f"α = {alpha}:")
        w("")
        w("| c_x² | φ (DSMC) | φ₁ | φ₂ | φ₃ |")
        w("|---|---|---|---|---|")
        for x2 in (0.25, 0.5, 1, 1.5, 2, 3, 4, 5, 6, 8, 10):
            k = int(np.argmin(np.abs(centres ** 2 - x2)))
            w(f"| {centres[k] ** 2:.2f} | {fmt(phi[k], phe[k] if phe is not None else float('nan'), 2)} | "
              f"{p1[k]:.2f} | {p2[k]:.2f} | {p3[k]:.2f} |")
        w("")

    # Fig. 7
    w("## Fig. 7: β₁(c_x²)/b′₁ (Eq. 4.6)")
    w("")
    w("β₁ is computed from the particles, not from the histogram: with φ of Eq. 4.3, β₁(X) = (4/3ε*)")
    w("⟨c_x(3/2 − c_x²) 1{c_x² < X}⟩ exactly (the `heat_flux` documentation), so β₁(∞) = b′₁ of Eq. 3.12.")
    w("")
    w("| α | β₁(6)/b′₁ (DSMC) | paper |")
    w("|---|---|---|")
    for c in cp:
        v, e = c.scalar("beta1_6_over_b1")
        paper = PAPER_BETA6.get(round(c.alpha, 3))
        w(f"| {c.alpha:.1f} | {fmt(v, e)} | {paper if paper else ''} |")
    w("")
    w("| c_x² | " + " | ".join(f"α = {c.alpha:.1f}" for c in cp) + " |")
    w("|---|" + "---|" * len(cp))
    X0, _ = cp[0].array("beta1_X")
    for x in (1, 2, 3, 4, 6, 8, 10, 12):
        k = int(np.argmin(np.abs(X0 - x)))
        vals = []
        for c in cp:
            r, re = c.array("beta1_over_b1")
            vals.append(fmt(r[k], re[k] if re is not None else float("nan"), 2))
        w(f"| {X0[k]:.2f} | " + " | ".join(vals) + " |")
    w("")

    # kappa
    w("## Beyond the paper: κ and μ")
    w("")
    w("κ from the steady Eq. 3.17 (`heat_flux_force` with `route: kappa`, `cloning_annihilation`, the thermostat);")
    w("μ n/(Tκ₀) = 2(κ − κ′)/κ₀ (Eq. 2.38) with κ′ from the κ′ sweep above. The time route is independent of the")
    w("cloning algorithm: the force G is switched on at t = 0 without the stochastic term and κ/κ₀ =")
    w("Σ e^{ζt/2} ΔK(t) over the records of K(t) = −q_x/(Tεκ₀) up to t = 15τ (the solution of Eq. 2.28 as")
    w(f"∫₀^∞ e^{{ζs/2}} ∂_s δf ds, docs/heat-flux-kappa.md), with ζ from Eq. 2.14; {Kt} realizations. It starts")
    w("from a Maxwellian, not the HCS, which is exact at α = 1 and differs by a₂ (|a₂| < 0.015 at α ≥ 0.7) below.")
    w("")
    w("| α | κ/κ₀ (Eq. 3.17) | κ/κ₀ (time route) | first Sonine (2.41) | κ′/κ₀ (DSMC) | μn/(Tκ₀) (DSMC) | μn/(Tκ₀) first Sonine |")
    w("|---|---|---|---|---|---|---|")
    tr = {round(c.alpha, 3): c for c in ct}
    kp_by_alpha = {round(c.alpha, 3): c.steady("conductivity_over_kappa0") for c in cp}
    for c in ck:
        k, e = c.steady("conductivity_over_kappa0")
        a2, zeta, nu, kp_th, k_th = sonine(c.alpha)
        kp, kpe = kp_by_alpha.get(round(c.alpha, 3), (float("nan"), float("nan")))
        mu, mue = 2 * (k - kp), 2 * np.hypot(e, kpe)
        t_route = "—"
        if round(c.alpha, 3) in tr:
            m, me, _ = time_route_kappa(tr[round(c.alpha, 3)], zeta * NU0_TAU0, 15.0)
            t_route = fmt(m, me)
        w(f"| {c.alpha:.1f} | {fmt(k, e)} | {t_route} | {k_th:.3f} | {fmt(kp, kpe)} | {fmt(mu, mue)} | {2 * (k_th - kp_th):.3f} |")
    w("")
    w(f"Cost per κ point: {sec['kappa'] / max(1, len(ck)):.0f} s of one core for {Kk} realizations of N = {N} over 25τ "
      f"(κ′: {sec['kappa_prime'] / max(1, len(cp)):.0f} s).")
    w("")
    w("## Findings")
    w("")
    w("- **Reproduced:** the shape of Fig. 3 — the first-Sonine κ′ is close for α ≳ 0.8 and overestimates")
    w("  increasingly below (by 23 % at α = 0.3); Fig. 4 — b′₁ varies little with α while b′₂ and b′₃ grow to")
    w("  the size of b′₁ at α = 0.3; Fig. 1 — steady after about ten collisions per particle, and q_x linear in ε*")
    w("  between 0.025 and 0.05; Eq. 3.10 and Eq. 3.12 give the same b′₁ and b′₂ (b′₃: see Fig. 4); Fig. 7 — the share of b′₁ carried by")
    w("  c_x² ≤ 6 is the paper's 66 % at α = 0.3.")
    w("- **κ by Eq. 3.17 is confirmed by the time route** at α = 0.9, 0.8, 0.7 (table above): the")
    w("  cloning–annihilation algorithm solves Eq. 2.28. Like κ′, κ falls below its first-Sonine value for")
    w("  α ≲ 0.7, and μ with it — the behaviour Brey et al. found with Green–Kubo (001, ref. 11).")
    w("- **The elastic anchor** is measured by long runs in docs/validation/heat-flux-anchor.md, extrapolated to")
    w("  ε* → 0 (the O(ε*²) response) and δt → 0 (the O(δt) bias of sampling q_x after the force and the")
    w("  thermostat, +0.3 % per 0.01τ): κ′(0)/κ₀ = 1.0237 ± 0.0016 against 1.025218 (−0.9 errors). The α = 1 row")
    w("  above comes from this report's short runs (25τ, averaged from 10τ) at ε* = 0.025 and carries both")
    w("  effects (+0.4 % and +0.1 % at δt = 0.003τ) and more: short runs sit above long runs at equal ε* and δt")
    w("  (+0.7 ± 0.25 % at ε* = 0.05, δt = 0.01τ; N = 2·10⁵ against 2·10⁴ alone gives +0.2 ± 0.2 %). Open: what")
    w("  raises the short runs (start-up transient, or errors from 16 realization means that are too small);")
    w("  it may shift every κ′ of Fig. 3 by about 1 %, small beside the first-Sonine differences.")
    w("- **Errors** are those of 4 realization means (3 degrees of freedom): a 3-error band holds the truth")
    w("  about 94 % of the time, not 99.7 %; the paper's 200 realizations were not matched.")
    w("")
    print("\n".join(out))


if __name__ == "__main__":
    main()
