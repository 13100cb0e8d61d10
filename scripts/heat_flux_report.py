#!/usr/bin/python3
"""Turn the HDF5 files of scripts/validate-heat-flux into docs/validation/heat-flux.md: paper 001's
modified thermal conductivity kappa', the Sonine coefficients b'_k, the distribution phi(c_x^2)
and beta1 (Figs. 1-7), and kappa itself from the steady Eq. 3.17 and from the time route, beside
the first-Sonine theory that the heat_flux diagnostic writes (Eqs. 2.14, 2.16, 2.41, 2.42, 2.46; its curves over
alpha from heat_flux 1.3.0 on) and the converged elastic value; the report computes no theory itself.

Usage: heat_flux_report.py DIR [DOCDIR] > DOCDIR/heat-flux.md
DIR holds the outputs of scripts/validate-heat-flux, found by their provenance (scripts/report_runs.py),
whatever their file names: configs/heat_flux_sweep.yaml (kappa'), the same with forcings.0.route=kappa
(the time route), configs/heat_flux_kappa_sweep.yaml, configs/heat_flux.yaml at forcings.0.epsilon_star=0.05
and, if run, configs/heat_flux.yaml swept over eps* (the anchor); and NAME.seconds (wall times) written
by the script for its runs kappa_prime, kappa, linearity and time_route.
The figures (the paper's Figs. 1-7 drawn from the same data as the tables, the alpha = 1 anchor
against eps* and kappa, mu against alpha) go to DOCDIR/heat-flux/*.png, DOCDIR being
docs/validation unless given.
Needs Debian's python3-h5py, python3-numpy and python3-matplotlib."""
import os
import sys

import h5py
import numpy as np

import report_runs
from report_figures import band, band_upper, paper_hline, paper_points, paper_vline, plt, runs_line, savefig, seed_check

PAPER_BETA6 = {1.0: 0.87, 0.3: 0.66}  # 001 Sec. IV: share of b'_1 carried by c_x^2 <= 6
FIGDIR = "heat-flux"  # under DOCDIR
STEADY_FROM = 10.0  # t/tau: the averaging window starts here (average_after of the configs)
FIG2_ALPHAS = (1.0, 0.3)  # the panels of Fig. 2
FIG5_ALPHAS = (1.0, 0.9)  # the panels of Fig. 5
FIG6_ALPHAS = (0.7, 0.5, 0.3)  # the panels of Fig. 6
FIG7_ALPHAS = (1.0, 0.9, 0.7, 0.5, 0.3)  # the curves of Fig. 7
SONINE_COLOURS = ("C0", "C1", "C2")  # b'_1, b'_2, b'_3
SONINE_MARKERS = ("o", "s", "^")  # as the paper's Fig. 4: circles, squares, triangles


def weighted_fit(A, y, e):
    """Weighted least squares y ~ A c with standard errors e: (coefficients, covariance, chi^2)."""
    W = np.diag(1 / e ** 2)
    cov = np.linalg.inv(A.T @ W @ A)
    c = cov @ A.T @ W @ y
    return c, cov, float(np.sum(((A @ c - y) / e) ** 2))


# nu0 tau0 at T0 (Eq. 2.15) for outputs of heat_flux before 1.3.0, which did not write nu0_tau0.
NU0_TAU0_BEFORE_1_3 = 8 / (5 * np.sqrt(np.pi))
CURVES_FROM = 0.28  # the theory curves are drawn over alpha in [CURVES_FROM, 1]


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

    def theory(self, name):
        """A theory scalar the heat_flux diagnostic wrote (first Sonine at this case's alpha)."""
        return float(self.d[name][()])

    def nu0_tau0(self):
        return self.theory("nu0_tau0") if "nu0_tau0" in self.d else NU0_TAU0_BEFORE_1_3


def theory_line(ax, cs, name, **style):
    """Draw the plugin's first-Sonine curve NAME_vs_alpha of the first case over alpha >= CURVES_FROM; an
    output written before heat_flux 1.3.0 has no curves: then a line through the cases' scalar NAME,
    and the legend says so."""
    d = cs[0].d
    if name + "_vs_alpha" in d:
        grid, values = np.array(d["theory_alpha_grid"][:]), np.array(d[name + "_vs_alpha"][:])
        keep = grid >= CURVES_FROM - 1e-9
        ax.plot(grid[keep], values[keep], **style)
        return
    ordered = sorted(cs, key=lambda c: c.alpha)
    style["label"] = style.get("label", "") + " (through the cases' values: no curve in this output)"
    ax.plot([c.alpha for c in ordered], [c.theory(name) for c in ordered], **style)


def elastic_reference(cs):
    """The converged Sonine kappa/kappa0 at alpha = 1 (001, ref. 37) that heat_flux writes."""
    return cs[0].theory("elastic_reference_kappa_over_kappa0")


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


def short_anchor(runs):
    """The path of the alpha = 1 anchor of many short realizations among runs (report_runs.Runs):
    configs/heat_flux.yaml swept over eps*; None if absent."""
    o = runs.one(config="heat_flux", axes=("forcings.0.epsilon_star",))
    return o.path if o else None


def anchor_extrapolation(path):
    """The alpha = 1 anchor run of many short realizations (configs/heat_flux.yaml swept over eps*): its cases, realizations,
    eps*, kappa'/kappa0 with errors, and the weighted fit kappa'(0) + c eps*^2 (q_x is odd in eps*)."""
    fa = h5py.File(path, "r")
    ca = cases(fa)
    eps = np.array([float(c.scalar("epsilon_star")[0]) for c in ca])
    kv = np.array([c.steady("conductivity_over_kappa0")[0] for c in ca])
    ke = np.array([c.steady("conductivity_over_kappa0")[1] for c in ca])
    coef, cov, chi2 = weighted_fit(np.vstack([np.ones_like(eps), eps ** 2]).T, kv, ke)
    return ca, int(fa.attrs["realizations"]), eps, kv, ke, coef, cov, chi2


def student_t_coverage(x, dof):
    """P(|t| < x) for Student's t with dof degrees of freedom (numerical integral of the density)."""
    from math import gamma, pi, sqrt
    u = np.linspace(0.0, x, 20001)
    pdf = gamma((dof + 1) / 2) / (sqrt(dof * pi) * gamma(dof / 2)) * (1 + u * u / dof) ** (-(dof + 1) / 2)
    return float(2 * np.sum(0.5 * (pdf[1:] + pdf[:-1]) * np.diff(u)))


def by_alpha(cs, alpha):
    return [c for c in cs if abs(c.alpha - alpha) < 1e-9][0]


def phi_curves(c):
    """c_x^2 of the bins (c_x > 0), phi and its error, phi_1..3 (Eqs. 3.15, 4.3, 4.5)."""
    phi, phe = c.array("phi")
    edges = c.edges("phi")
    centres = 0.5 * (edges[1:] + edges[:-1])
    p = [c.array(f"phi_{k}")[0] for k in (1, 2, 3)]
    return centres ** 2, phi, phe, p


def figure_1(c03, cl, docdir):
    """Paper Fig. 1: kappa'(t)/kappa0 at alpha = 0.3 for eps* = 0.025 (solid) and 0.05 (dashed)."""
    fig, ax = plt.subplots(figsize=(7, 4.4))
    t1, (y1, e1) = c03.time(), c03.series("conductivity_over_kappa0")
    t2, (y2, e2) = cl.time(), cl.series("conductivity_over_kappa0")
    ax.axvspan(STEADY_FROM, t1[-1], color="0.93", zorder=0, label=f"steady window, t ≥ {STEADY_FROM:g}τ")
    band(ax, t1, y1, e1, color="C0", linewidth=1.4, label=f"ε* = {c03.scalar('epsilon_star')[0]:g}")
    band(ax, t2, y2, e2, color="C3", linewidth=1.4, linestyle="--", label=f"ε* = {cl.scalar('epsilon_star')[0]:g}")
    k, e = c03.steady("conductivity_over_kappa0")
    ax.axhline(k, color="k", linestyle=":", linewidth=1.3,
               label=f"steady value, ε* = {c03.scalar('epsilon_star')[0]:g}: {k:.3f} ± {e:.3f}")
    ax.set_xlim(0, t1[-1])
    ax.set_ylim(0, None)
    ax.set_xlabel("t / τ")
    ax.set_ylabel(r"$\kappa'(t)/\kappa_0$")
    ax.set_title("Fig. 1: α = 0.3 (bands: ± one standard error)", fontsize=10)
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    return savefig(fig, docdir, FIGDIR, "fig1_kappa_prime_t")


def figure_2(cp, docdir):
    """Paper Fig. 2: b'_k(t) at alpha = 1 (top) and 0.3 (bottom); solid Eq. 3.10, dashed Eq. 3.12,
    dotted the steady values (Eq. 3.10)."""
    fig, axes = plt.subplots(len(FIG2_ALPHAS), 1, figsize=(7.5, 7.8), sharex=True)
    for ax, alpha in zip(axes, FIG2_ALPHAS):
        c = by_alpha(cp, alpha)
        t = c.time()
        ax.axvspan(STEADY_FROM, t[-1], color="0.93", zorder=0)
        for k, colour in zip((1, 2, 3), SONINE_COLOURS):
            y, e = c.series(f"b{k}_full")
            band(ax, t, y, e, color=colour, linewidth=1.4)
            ym, em = c.series(f"b{k}_marginal")
            band(ax, t, ym, em, alpha=0.12, color=colour, linewidth=1.1, linestyle="--")
            ax.axhline(c.steady(f"b{k}_full")[0], color=colour, linestyle=":", linewidth=1.2)
        ax.axhline(0, color="0.6", linewidth=0.6)
        ax.set_ylabel(r"$b'_k(t)$")
        ax.set_title(f"α = {alpha:g}", fontsize=10, loc="left")
        ax.set_xlim(0, t[-1])
    axes[-1].set_xlabel("t / τ")
    handles = [plt.Line2D([], [], color=col, linewidth=1.4, label=f"$b'_{k}$")
               for k, col in zip((1, 2, 3), SONINE_COLOURS)]
    handles += [plt.Line2D([], [], color="k", linewidth=1.4, label=r"Eq. 3.10, $\langle c_x L_k^{(3/2)}(c^2)\rangle$"),
                plt.Line2D([], [], color="k", linewidth=1.1, linestyle="--",
                           label=r"Eq. 3.12, $\langle c_x L_k^{(1/2)}(c_x^2)\rangle$"),
                plt.Line2D([], [], color="k", linewidth=1.2, linestyle=":", label="steady value (Eq. 3.10)"),
                plt.Rectangle((0, 0), 1, 1, color="0.93", label=f"steady window, t ≥ {STEADY_FROM:g}τ")]
    fig.suptitle("Fig. 2: Sonine coefficients against time (bands: ± one standard error)", fontsize=10)
    fig.legend(handles=handles, loc="lower center", ncol=4, fontsize=8.5, bbox_to_anchor=(0.5, -0.005))
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    return savefig(fig, docdir, FIGDIR, "fig2_sonine_t")


def figure_3(cp, docdir):
    """Paper Fig. 3: kappa'/kappa0 against alpha, the first Sonine (2.42) and the paper's arrow."""
    fig, ax = plt.subplots(figsize=(7, 4.6))
    theory_line(ax, cp, "theory_kappa_prime_over_kappa0", color="k", linewidth=1.3, label="first Sonine, Eqs. 2.42, 2.46")
    a = [c.alpha for c in cp]
    k = [c.steady("conductivity_over_kappa0") for c in cp]
    ax.errorbar(a, [v for v, _ in k], yerr=[e for _, e in k], fmt="o", color="C0", markersize=6, capsize=3,
                label="DSMC, ε* = 0.025 (± one standard error)")
    paper_points(ax, [1.02], [elastic_reference(cp)], marker="<", markersize=9,
                 label=f"paper's arrow: converged Sonine κ/κ₀ = {elastic_reference(cp)} at α = 1")
    ax.set_xlim(0.25, 1.045)
    ax.set_xlabel("coefficient of normal restitution α")
    ax.set_ylabel(r"$\kappa'/\kappa_0$")
    ax.set_title("Fig. 3 (the paper's Green–Kubo triangles of ref. 11 are not given as numbers)", fontsize=9.5)
    ax.legend(fontsize=8.5, loc="upper right")
    fig.tight_layout()
    return savefig(fig, docdir, FIGDIR, "fig3_kappa_prime")


def figure_anchor(eps, kv, ke, coef, cov, elastic, docdir):
    """kappa'/kappa0 at alpha = 1 against eps*^2 with the weighted fit kappa'(0) + c eps*^2."""
    fig, ax = plt.subplots(figsize=(7, 4.4))
    x = np.linspace(0, 1.05 * float(np.max(eps ** 2)), 100)
    A = np.vstack([np.ones_like(x), x]).T
    fit = A @ coef
    fit_e = np.sqrt(np.einsum("ij,jk,ik->i", A, cov, A))
    band(ax, x, fit, fit_e, color="C0", linewidth=1.2,
         label=f"weighted fit: κ′(0)/κ₀ = {coef[0]:.4f} ± {np.sqrt(cov[0, 0]):.4f}, c = {coef[1]:.2f} ± {np.sqrt(cov[1, 1]):.2f}")
    ax.errorbar(eps ** 2, kv, yerr=ke, fmt="o", color="C0", markersize=6, capsize=3,
                label="DSMC, α = 1, δt = 0.03τ (± one standard error)")
    paper_hline(ax, elastic, label=f"converged Sonine κ/κ₀ = {elastic} (paper's Fig. 3 arrow)")
    ax.set_xlim(-0.0003, x[-1])
    top = ax.secondary_xaxis("top", functions=(lambda v: np.sqrt(np.clip(v, 0, None)), lambda v: v ** 2))
    top.set_xticks([e_ for e_ in eps if e_ >= 0.02])
    top.set_xlabel(r"$\epsilon^*$", fontsize=9)
    ax.set_xlabel(r"$\epsilon^{*2}$")
    ax.set_ylabel(r"$\kappa'/\kappa_0$ at α = 1")
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    return savefig(fig, docdir, FIGDIR, "anchor_against_epsilon")


def figure_4(cp, docdir):
    """Paper Fig. 4: b'_1 (circles), b'_2 (squares), b'_3 (triangles) against alpha, lines as guides;
    Eq. 3.12 as open markers beside them, and the first-Sonine b'_1."""
    fig, ax = plt.subplots(figsize=(9.5, 5.0))
    a = np.array([c.alpha for c in cp])
    theory_line(ax, cp, "theory_b1", color="C0", linestyle="--", linewidth=1.1,
                label=r"first-Sonine $b'_1$ (Eq. 2.45 with 2.42)")
    for k, colour, m in zip((1, 2, 3), SONINE_COLOURS, SONINE_MARKERS):
        full = np.array([c.steady(f"b{k}_full") for c in cp])
        marg = np.array([c.steady(f"b{k}_marginal") for c in cp])
        ax.errorbar(a, full[:, 0], yerr=full[:, 1], fmt=m + "-", color=colour, markersize=6, capsize=3,
                    linewidth=1.0, label=f"$b'_{k}$, Eq. 3.10")
        ax.errorbar(a + 0.012, marg[:, 0], yerr=marg[:, 1], fmt=m, color=colour, markersize=5, capsize=2,
                    markerfacecolor="none", linewidth=0.8, label=f"$b'_{k}$, Eq. 3.12 (shifted +0.012 in α)")
    ax.axhline(0, color="0.6", linewidth=0.6)
    ax.set_xlim(0.25, 1.05)
    ax.set_xlabel("coefficient of normal restitution α")
    ax.set_ylabel(r"$b'_k$")
    ax.set_title("Fig. 4 (bars: ± one standard error)", fontsize=10)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    return savefig(fig, docdir, FIGDIR, "fig4_sonine_coefficients")


def figure_phi(cp, alphas, name, title, docdir):
    """Paper Figs. 5-6: phi(c_x^2) (solid, band of one standard error) and phi_1, phi_2, phi_3
    (dotted, dash-dotted, dashed) from the measured b'_k."""
    fig, axes = plt.subplots(len(alphas), 1, figsize=(7, 2.9 * len(alphas) + 0.8), sharex=True)
    xmax = 10.0
    for ax, alpha in zip(axes, alphas):
        x2, phi, phe, p = phi_curves(by_alpha(cp, alpha))
        keep = x2 <= xmax + 0.3
        band(ax, x2[keep], phi[keep], None if phe is None else phe[keep], color="k", linewidth=1.6, label="φ (DSMC)")
        for pk, ls, colour, lab in zip(p, (":", "-.", "--"), ("C0", "C2", "C3"), ("φ₁", "φ₂", "φ₃")):
            ax.plot(x2[keep], pk[keep], color=colour, linestyle=ls, linewidth=1.4, label=lab)
        lo, hi = np.nanmin(phi[keep]), np.nanmax(phi[keep])
        pad = 0.12 * (hi - lo)
        ax.set_ylim(lo - pad, hi + pad)
        ax.axhline(0, color="0.6", linewidth=0.6)
        ax.set_ylabel(r"$\varphi(c_x^2)$")
        ax.set_title(f"α = {alpha:g}", fontsize=10, loc="left")
        ax.legend(fontsize=8, loc="lower left", ncol=2)
    axes[-1].set_xlim(0, xmax)
    axes[-1].set_xlabel(r"$c_x^2$")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return savefig(fig, docdir, FIGDIR, name)


def figure_7(cp, docdir):
    """Paper Fig. 7: beta1(c_x^2)/b'_1 for alpha = 1, 0.9, 0.7, 0.5, 0.3; the paper's 87 % and 66 %
    at c_x^2 = 6."""
    fig, ax = plt.subplots(figsize=(7, 4.6))
    for alpha, colour in zip(FIG7_ALPHAS, ("C0", "C1", "C2", "C3", "C4")):
        c = by_alpha(cp, alpha)
        X, _ = c.array("beta1_X")
        r, re = c.array("beta1_over_b1")
        band(ax, X, r, re, color=colour, linewidth=1.4, label=f"α = {alpha:g}")
    paper_vline(ax, 6.0)
    paper_points(ax, [6.0, 6.0], [PAPER_BETA6[1.0], PAPER_BETA6[0.3]],
                 label=f"paper at $c_x^2$ = 6: {PAPER_BETA6[1.0]:g} (α = 1), {PAPER_BETA6[0.3]:g} (α = 0.3)")
    ax.axhline(1, color="0.6", linewidth=0.6)
    ax.set_xlim(0, float(X[-1]))
    ax.set_ylim(0, 1.08)
    ax.set_xlabel(r"$c_x^2$")
    ax.set_ylabel(r"$\beta_1(c_x^2)/b'_1$")
    ax.set_title("Fig. 7 (bands: ± one standard error)", fontsize=10)
    ax.legend(fontsize=8.5, loc="lower right")
    fig.tight_layout()
    return savefig(fig, docdir, FIGDIR, "fig7_beta1")


def figure_kappa_mu(ck, rows, docdir):
    """Beyond the paper: kappa/kappa0 (Eq. 3.17 and time route) and mu n/(T kappa0) against alpha."""
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.6))
    a = np.array([r["alpha"] for r in rows])
    ax = axes[0]
    theory_line(ax, ck, "theory_kappa_over_kappa0", color="C0", linewidth=1.3, label="κ, first Sonine (2.41)")
    theory_line(ax, ck, "theory_kappa_prime_over_kappa0", color="C1", linewidth=1.1, linestyle="--",
                label="κ′, first Sonine (2.42)")
    ax.errorbar(a, [r["k"] for r in rows], yerr=[r["ke"] for r in rows], fmt="o", color="C0", capsize=3,
                markersize=6, label="κ, DSMC Eq. 3.17")
    tr = [r for r in rows if r["tr"] is not None]
    ax.errorbar([r["alpha"] + 0.012 for r in tr], [r["tr"][0] for r in tr], yerr=[r["tr"][1] for r in tr], fmt="s",
                color="C2", markerfacecolor="none", capsize=3, markersize=6, label="κ, DSMC time route (shifted +0.012 in α)")
    ax.errorbar(a, [r["kp"] for r in rows], yerr=[r["kpe"] for r in rows], fmt="^", color="C1", capsize=3,
                markersize=6, label="κ′, DSMC (Fig. 3)")
    paper_points(ax, [1.02], [elastic_reference(ck)], marker="<", markersize=9, label=f"converged Sonine {elastic_reference(ck)} at α = 1")
    ax.set_ylabel(r"$\kappa/\kappa_0$, $\kappa'/\kappa_0$")
    ax.legend(fontsize=8, loc="upper right")
    ax = axes[1]
    theory_line(ax, ck, "theory_mu_n_over_T_kappa0", color="C3", linewidth=1.3, label="first Sonine, 2(κ − κ′)/κ₀")
    ax.errorbar(a, [r["mu"] for r in rows], yerr=[r["mue"] for r in rows], fmt="o", color="C3", capsize=3,
                markersize=6, label="DSMC, 2(κ − κ′)/κ₀ (Eq. 2.38)")
    ax.axhline(0, color="0.6", linewidth=0.6)
    ax.set_ylabel(r"$\mu n/(T\kappa_0)$")
    ax.legend(fontsize=8, loc="upper right")
    for ax in axes:
        ax.set_xlim(0.25, 1.045)
        ax.set_xlabel("coefficient of normal restitution α")
    axes[0].set_title("thermal conductivity (bars: ± one standard error)", fontsize=10)
    axes[1].set_title("the coefficient μ of the heat flux ∝ ∇n", fontsize=10)
    fig.tight_layout()
    return savefig(fig, docdir, FIGDIR, "kappa_mu")


def main():
    d = sys.argv[1]
    docdir = sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..",
                                                                 "docs", "validation")
    out = []
    w = out.append
    found = report_runs.index(d)
    selected = {"κ′ sweep (configs/heat_flux_sweep.yaml)": found.one(config="heat_flux_sweep", unset=("forcings.0.route",)),
                "κ sweep (configs/heat_flux_kappa_sweep.yaml)": found.one(config="heat_flux_kappa_sweep"),
                "linearity (configs/heat_flux.yaml, forcings.0.epsilon_star=0.05)":
                    found.one(config="heat_flux", set={"forcings.0.epsilon_star": "0.05"}, axes=()),
                "time route (configs/heat_flux_sweep.yaml, forcings.0.route=kappa)":
                    found.one(config="heat_flux_sweep", set={"forcings.0.route": "kappa"})}
    missing = [k for k, o in selected.items() if o is None]
    if missing:
        raise SystemExit(f"heat_flux_report: not in {d}: " + "; ".join(missing) + " (run scripts/validate-heat-flux)")
    fp, fk, fl, ft = (h5py.File(o.path) for o in selected.values())
    anchor_path = short_anchor(found)
    cp, ck, cl, ct = cases(fp), cases(fk), cases(fl)[0], cases(ft)
    elastic = elastic_reference(cp)
    K = int(fp.attrs["realizations"])
    Kk = int(fk.attrs["realizations"])
    Kt = int(ft.attrs["realizations"])
    N = int(cp[0].g["system"].attrs["particles"]) if "particles" in cp[0].g["system"].attrs else 200000
    sec = {n: seconds(d, n) for n in ("kappa_prime", "kappa", "linearity", "time_route")}

    w("# Validation: thermal conductivity of the granular gas by a homogeneous heat-flux force (paper 001)")
    w("")
    runs = [o.path for o in selected.values()] + ([anchor_path] if anchor_path else [])
    w("Every path named in this document is in the source tree. Generated by `scripts/validate-heat-flux` (`scripts/heat_flux_report.py`); do not edit by hand; "
      + runs_line(*runs) + ".")
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
    w("Both sweeps ran at the same time on the two cores (each run uses every core by default, `run.threads`). At δt = 0.003τ a particle collides once per ~300 steps,")
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
        th = c.theory("theory_kappa_prime_over_kappa0")
        w(f"| {c.alpha:.1f} | {fmt(k, e)} | {th:.3f} | {k - th:+.3f} |")
        if abs(c.alpha - 1) < 1e-9:
            anchor = (k, e)
    w("")
    w("The paper's Fig. 3: DSMC (± one standard error) beside the first-Sonine line; the paper's arrow, the")
    w(f"converged Sonine value {elastic} at α = 1, as an open marker.")
    w("")
    w(figure_3(cp, docdir))
    w("")
    if anchor:
        k, e = anchor
        z = (k - elastic) / e
        w(f"**The paper's anchor.** At α = 1, κ′ = κ and the converged Sonine value is κ/κ₀ = {elastic}. "
          f"gdsmc: {fmt(k, e, 4)}, {z:+.1f} standard errors from it; the first-Sonine value 1 is "
          f"{(k - 1) / e:+.1f} errors away.")
        w("")

    # The anchor against eps*
    anchor_fit = None
    anchor_bracketed = False  # the anchor runs sample before and after the collisions (no O(δt) bias of sampling)
    anchor_seed_outside = []  # (ε*, χ²/dof) of heat_flux's own error above the seed check's band
    if anchor_path:
        ca, Ka, eps, kv, ke, coef, cov, chi2 = anchor_extrapolation(anchor_path)
        w("**The anchor against the field strength.** Linear response is the limit ε* → 0 (Eq. 3.9), and q_x")
        w(f"is odd in ε*, so κ′(ε*) = κ′(0) + c ε*² + O(ε*⁴). At α = 1, δt = 0.03τ, {Ka} realizations per ε*:")
        w("")
        # Issue 29 item 2: each realization's own errors of κ′ against the realizations' scatter (gdsmc's seed check).
        checks = []
        for c in ca:
            rows, band_text, _ = seed_check(c.d, [("own", "conductivity_over_kappa0_mean", "conductivity_over_kappa0_standard_error"),
                                                   ("host", "conductivity_over_kappa0.steady_mean",
                                                    "conductivity_over_kappa0.steady_stderr")])
            checks.append(({r[0]: r[3] for r in rows}, band_text))
            anchor_bracketed = str(c.d.attrs.get("sampling", "")).startswith("bracketed")
            high = band_upper(band_text)
            try:
                own = float(checks[-1][0].get("own", "nan"))
            except ValueError:  # "— (n own errors NaN)"
                own = float("nan")
            if own > high:
                anchor_seed_outside.append((float(c.scalar("epsilon_star")[0]), own, band_text))
        w("| ε* | κ′/κ₀ | seed check of heat_flux's own error (χ²/dof) | of the host's steady error |")
        w("|---|---|---|---|")
        for e_, k_, ke_, (chk, _) in zip(eps, kv, ke, checks):
            w(f"| {e_:g} | {fmt(k_, ke_, 4)} | {chk.get('own', '—')} | {chk.get('host', '—')} |")
        w("")
        w(f"The seed checks (issue 29 item 2): χ²/dof of the {Ka} realizations' κ′ about their mean against the mean of")
        w(f"their own errors squared, 1 when one run's error holds (95 % band {checks[0][1] if checks else '—'}; user guide,")
        w("\"The seed check of every error\"). The κ′ quoted is the realizations' mean with the error of their scatter.")
        if any(str(chk.get("host", "")).startswith("—") for chk, _ in checks):
            w("Where the host's column has no χ², its steady error of one realization is NaN: the window holds fewer than 4")
            w("batches of 5 integrated autocorrelation times of κ′ (the reason is in each error's description), and the host")
            w("gives no error rather than one that is too small.")
        w("")
        k0, k0e = coef[0], np.sqrt(cov[0, 0])
        anchor_fit = (k0, k0e)
        w(f"Weighted fit: κ′(0)/κ₀ = {fmt(k0, k0e, 4)} ({(k0 - elastic) / k0e:+.1f} errors from {elastic}), "
          f"c = {coef[1]:.2f} ± {np.sqrt(cov[1, 1]):.2f}, χ² = {chi2:.1f} for {len(eps) - 2} degrees of freedom.")
        w("")
        w(figure_anchor(eps, kv, ke, coef, cov, elastic, docdir))
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
        row.append(f"{c.theory('theory_b1'):.3f}")
        w("| " + " | ".join(row) + " |")
    w("")
    routes = {}  # k -> [(alpha, Eq. 3.12 - Eq. 3.10, that over the errors in quadrature)]
    for k in (1, 2, 3):
        routes[k] = []
        for c in cp:
            (f, fe), (m, me) = c.steady(f"b{k}_full"), c.steady(f"b{k}_marginal")
            routes[k].append((c.alpha, m - f, (m - f) / np.hypot(fe, me)))
    z12 = max((abs(z), a, k) for k in (1, 2) for a, _, z in routes[k])
    above3 = [(a, dv, z) for a, dv, z in routes[3] if dv > 0]
    w("Eq. 3.10 and Eq. 3.12 estimate the same coefficient from the same particles (the paper's Appendix, in the")
    w(f"linear regime). b′₁ and b′₂ by the two routes differ by at most {z12[0]:.1f} errors (b′{'₁₂'[z12[2] - 1]} at "
      f"α = {z12[1]:g}; the two errors added in quadrature, which overstates the error of a difference of")
    w(f"correlated estimates); b′₃ by Eq. 3.12 lies above Eq. 3.10 at {len(above3)} of {len(routes[3])} α"
      + (f", by {min(dv for _, dv, _ in above3):.3f}–{max(dv for _, dv, _ in above3):.3f} (up to "
         f"{max(z for _, _, z in above3):.1f} errors)" if above3 else "")
      + " — the paper saw the two distinguishable only for b′₃ at α = 0.3.")
    w("L₃^(1/2)(c_x²) weights c_x⁷, so this moment is the most sensitive to the O(ε*³) response and to the tail;")
    w("not investigated further.")
    w("")
    w("The paper's Fig. 4 (circles, squares and triangles for b′₁, b′₂, b′₃ by Eq. 3.10, the lines guides to the eye),")
    w("with Eq. 3.12 beside it as open markers and the first-Sonine b′₁:")
    w("")
    w(figure_4(cp, docdir))
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
    w("The paper's Fig. 1 (solid ε* = 0.025, dashed ε* = 0.05, dotted the steady value at ε* = 0.025), with bands of")
    w("one standard error:")
    w("")
    w(figure_1(c03, cl, docdir))
    w("")

    # Fig. 2
    w("## Fig. 2: b′_k(t) at α = 1 and α = 0.3, by Eq. 3.10 (full) and Eq. 3.12 (marginal)")
    w("")
    w("The paper's Fig. 2 (α = 1 top, α = 0.3 bottom; solid Eq. 3.10, dashed Eq. 3.12, dotted the steady values):")
    w("")
    w(figure_2(cp, docdir))
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
    w("that of the realizations. φ_p uses the measured b′_k (Eq. 3.10). The paper's Figs. 5 and 6 (φ solid with a")
    w("band of one standard error; φ₁, φ₂, φ₃ dotted, dash-dotted and dashed, as the paper), the y range set by φ:")
    w("")
    w(figure_phi(cp, FIG5_ALPHAS, "fig5_phi", "Fig. 5: φ(c_x²) and its truncated Sonine series", docdir))
    w("")
    w(figure_phi(cp, FIG6_ALPHAS, "fig6_phi", "Fig. 6: φ(c_x²) and its truncated Sonine series", docdir))
    w("")
    w("The tables at selected c_x²:")
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
    w("The paper's Fig. 7 (its α = 1, 0.9, 0.7, 0.5, 0.3), with the shares it states at c_x² = 6 as open markers:")
    w("")
    w(figure_7(cp, docdir))
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
    rows = []
    for c in ck:
        k, e = c.steady("conductivity_over_kappa0")
        k_th, mu_th = c.theory("theory_kappa_over_kappa0"), c.theory("theory_mu_n_over_T_kappa0")
        kp, kpe = kp_by_alpha.get(round(c.alpha, 3), (float("nan"), float("nan")))
        mu, mue = 2 * (k - kp), 2 * np.hypot(e, kpe)
        t_route, route = "—", None
        if round(c.alpha, 3) in tr:
            tc = tr[round(c.alpha, 3)]
            m, me, _ = time_route_kappa(tc, tc.theory("theory_zeta0_over_nu0") * tc.nu0_tau0(), 15.0)
            t_route, route = fmt(m, me), (m, me)
        rows.append({"alpha": c.alpha, "k": k, "ke": e, "kp": kp, "kpe": kpe, "mu": mu, "mue": mue, "tr": route})
        w(f"| {c.alpha:.1f} | {fmt(k, e)} | {t_route} | {k_th:.3f} | {fmt(kp, kpe)} | {fmt(mu, mue)} | {mu_th:.3f} |")
    w("")
    w("The same against α: κ by both routes and κ′ beside their first-Sonine lines (left), μ (right):")
    w("")
    w(figure_kappa_mu(ck, rows, docdir))
    w("")
    w(f"Cost per κ point: {sec['kappa'] / max(1, len(ck)):.0f} s of wall time for {Kk} realizations of N = {N} over 25τ "
      f"(κ′: {sec['kappa_prime'] / max(1, len(cp)):.0f} s; the two sweeps shared the cores).")
    w("")
    route_z = [(r["alpha"], (r["k"] - r["tr"][0]) / np.hypot(r["ke"], r["tr"][1])) for r in rows if r["tr"] is not None]
    c03k = by_alpha(cp, 0.3).steady("conductivity_over_kappa0")[0]
    over03 = by_alpha(cp, 0.3).theory("theory_kappa_prime_over_kappa0") / c03k - 1
    b6 = {a: by_alpha(cp, a).scalar("beta1_6_over_b1") for a in (1.0, 0.3)}
    linear = abs(kb - ka) < 3 * np.hypot(ea_, eb_)
    w("## Findings")
    w("")
    w("- **Reproduced:** the shape of Fig. 3 — the first-Sonine κ′ is close for α ≳ 0.8 and overestimates")
    w(f"  increasingly below (by {100 * over03:.0f} % at α = 0.3); Fig. 4 — b′₁ varies little with α while b′₂ and b′₃ grow to")
    w("  the size of b′₁ at α = 0.3; Fig. 1 — steady after about ten collisions per particle, and q_x "
      + ("linear in ε*" if linear else "**not** linear in ε* within 3 errors"))
    w("  between 0.025 and 0.05; Eq. 3.10 and Eq. 3.12 give the same b′₁ and b′₂ (b′₃: see Fig. 4); Fig. 7 — the share of b′₁ carried by")
    w(f"  c_x² ≤ 6 at α = 0.3 is {100 * b6[0.3][0]:.1f} ± {100 * b6[0.3][1]:.1f} % against the paper's "
      f"{100 * PAPER_BETA6[0.3]:.0f} %.")
    w(f"- **κ by Eq. 3.17 against the time route** at α = {', '.join(f'{a:g}' for a, _ in route_z)}: "
      + ", ".join(f"{z:+.1f}" for _, z in route_z) + " errors (table above)"
      + (": the cloning–annihilation algorithm solves Eq. 2.28." if all(abs(z) < 3 for _, z in route_z)
         else ": **more than 3 errors apart somewhere** — not a confirmation."))
    w("  Like κ′, κ falls below its first-Sonine value for")
    w("  α ≲ 0.7, and μ with it — the behaviour Brey et al. found with Green–Kubo (001, ref. 11).")
    # The long runs of heat-flux-anchor.md, read from this directory (scripts/validate-heat-flux makes them first);
    # imported here, not at the top, because heat_flux_anchor_report imports this module.
    import heat_flux_anchor_report
    long = heat_flux_anchor_report.anchor(found)
    if long is None:
        w("- **The elastic anchor** by long runs (docs/validation/heat-flux-anchor.md): the outputs of")
        w("  configs/heat_flux_anchor.yaml and configs/heat_flux_anchor_dt.yaml are not in this directory, so the rows")
        w("  above are not compared with it.")
    else:
        L, Le, slope = long["value"], long["error"], long["slope"]
        w("- **The elastic anchor** is measured by long runs in docs/validation/heat-flux-anchor.md ("
          + long["runs"] + "), extrapolated to")
        w(f"  ε* → 0 (the O(ε*²) response, c = {long['c']:.2f}) and δt → 0 (what is left of the time step, "
          f"{slope:+.3f} ± {long['slope_error']:.3f} per τ): κ′(0)/κ₀ = {L:.4f} ± {Le:.4f}")
        w(f"  against {elastic} ({(L - elastic) / Le:+.1f} errors).")
        if anchor_bracketed:
            w("  The runs of this report sample bracketed (before and after the collision stage), as the long runs do,")
            w("  so the long runs' c ε*² and δt slope carry over:")
            if anchor:
                k1, e1 = anchor
                exp1 = L + long["c"] * 0.025 ** 2 + slope * 0.003
                w(f"  the α = 1 row above (short runs, 25τ averaged from 10τ, ε* = 0.025, δt = 0.003τ) should be {exp1:.4f};")
                w(f"  it is {fmt(k1, e1, 4)}, {(k1 - exp1) / np.hypot(e1, Le):+.1f} errors from that.")
            if anchor_fit:
                k0, k0e = anchor_fit
                exp0 = L + slope * 0.03
                w(f"  The ε* fit above (δt = 0.03τ) should be {exp0:.4f}; it is {fmt(k0, k0e, 4)}, "
                  f"{(k0 - exp0) / np.hypot(k0e, Le):+.1f} errors from that.")
        else:
            w("  The runs of this report sample after the step and the long runs bracketed, so their δt effects differ")
            w("  and the rows above are not compared with the long runs (rerun both with one `run.sampling`).")
    w("  On 2026-11-23 (gdsmc 0.3.1, by hand, not rerun here) short runs sat above long runs at equal ε* and δt")
    w("  (+0.7 ± 0.25 % at ε* = 0.05, δt = 0.01τ; N = 2·10⁵ against 2·10⁴ alone gives +0.2 ± 0.2 %), and that")
    w("  run of this report had 1.046 ± 0.004 in the α = 1 row and 1.0363 ± 0.0029 from the ε* fit. Open: whether")
    w("  that excess is real (a start-up transient) or the scatter of a few realization means whose errors are")
    w("  themselves uncertain; compare the two numbers above between runs. Either way it is about 1 % at most,")
    w("  small beside the first-Sonine differences of Fig. 3.")
    if anchor_seed_outside:
        w("- **Error bars (issue 29 item 2):** `heat_flux`'s own error of κ′ from one run understates the scatter of the")
        w("  anchor's realizations at ε* = " + ", ".join(f"{e:g} (χ²/dof {x:.2f})" for e, x, _ in anchor_seed_outside) +
          f", band {anchor_seed_outside[0][2]}: one run's `conductivity_over_kappa0_standard_error` is too small by")
        w("  √(χ²/dof). The κ′ of this report are the realizations' means with the error of their scatter, which")
        w("  this does not touch.")
    if anchor:
        k1, e1 = anchor
        tail = "more" if b6[1.0][0] < PAPER_BETA6[1.0] else "less"
        w(f"- **The α = 1 row at ε* = 0.025** (this run): κ′/κ₀ = {fmt(k1, e1)}, {(k1 - elastic) / e1:+.1f} errors "
          f"from {elastic}; β₁(6)/b′₁ = {fmt(*b6[1.0])} against the paper's {PAPER_BETA6[1.0]}")
        w(f"  ({(b6[1.0][0] - PAPER_BETA6[1.0]) / b6[1.0][1]:+.1f} errors: {tail} of b′₁ in the tail c_x² > 6 than the paper). "
          "Before the long anchor runs this row was an open finding, and what was")
        w("  tried then (2026-11-23, gdsmc 0.3.1, by hand, not rerun here): the time step (0.003, 0.01, 0.03τ: 1.046 ± 0.004,")
        w("  1.051 ± 0.005, 1.043 ± 0.007 — no dependence seen at that precision); N (2·10⁴ and 2·10⁵: the same); a")
        w("  48-realization run at ε* = 0.0125 (1.033 ± 0.005); an independent vectorised DSMC written without gdsmc code")
        w("  (`scripts/heat_flux_numpy_dsmc.py`: 1.048 ± 0.010 at ε* = 0.05, 4 runs; 1.026 ± 0.012 at 0.025, 6 runs),")
        w("  which reproduces gdsmc; the collision rate of the elastic gas (0.56375 collisions per particle per τ⁰")
        w("  against 1/√π = 0.56419) and the impact-direction sampling (σ̂ from ĝ + u: the scattered relative velocity")
        w("  is −|g|u, isotropic, as for hard spheres). Two other elastic transport measurements with gdsmc sit a few")
        w("  per cent from the converged Chapman–Enskog values, in different directions: plane Fourier flow between")
        w("  diffuse walls (Kn = 0.1, 80 layers, T_w = 0.9/1.1, central 3λ, `configs/fourier_elastic.yaml`) gives")
        w("  κ/κ₀ = 1.005 ± 0.007 (about 1.00 at Kn = 0.05), and uniform shear with this thermostat (a τ⁰ = 0.05 and")
        w("  0.025) gives η/η₀ = 0.974 ± 0.004 and 0.986 ± 0.007, about 0.99 at a → 0, against 1.016 (the Enskog")
        w("  report's dilute η/η₀ was 0.993 ± 0.014). Both were protocol biases, resolved in")
        w("  `docs/validation/sampling.md`: the Fourier flow's κ is 1.7 % low at L = 10 λ⁰ from the walls' Knudsen layers")
        w("  and agrees at L = 20 λ⁰ (1.0056 ± 0.0038 of κ_CE); the shear viscosity was sampled after the step, an O(δt)")
        w("  bias that bracketed sampling removes (η/η₀ = 1.0165 ± 0.0036 at δt = 0.04 τ⁰ against 1.0126 with the")
        w("  thermostat's thinning).")
    w(f"- **Errors** are those of {K} realization means ({K - 1} degrees of freedom): a 3-error band holds the truth")
    w(f"  about {100 * student_t_coverage(3.0, K - 1):.0f} % of the time, not 99.7 %; the paper's 200 realizations were not matched.")
    w("")
    print("\n".join(out))


if __name__ == "__main__":
    main()
