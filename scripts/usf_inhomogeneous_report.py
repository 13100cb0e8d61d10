#!/usr/bin/python3
"""Turn the HDF5 files of scripts/validate-usf-inhomogeneous into
docs/validation/usf-inhomogeneous.md: the inhomogeneous uniform shear flow of paper 000 (Sec. IV.A,
Figs. 1-4 and 9) beside the numbers the paper states and beside the homogeneous engine.

Usage: usf_inhomogeneous_report.py OUTPUTS... [--docdir DOCDIR] > DOCDIR/usf-inhomogeneous.md
OUTPUTS: folders of outputs (searched recursively, any file names) or output files. The runs are found by their provenance (scripts/report_runs.py): the outputs of
configs/usf_inhomogeneous_transient.yaml, of configs/usf_inhomogeneous_steady.yaml as it is and with
--set run.candidate_pairs=distinct, and of configs/usf_{ihs,ehs}_alpha0.9_shear4.yaml. The figures
(the paper's Figs. 1-4 and 9 drawn from the same data as the tables) go to
DOCDIR/usf-inhomogeneous/*.png, DOCDIR being docs/validation unless given.
Needs Debian's python3-h5py, python3-numpy and python3-matplotlib."""
import argparse
import os
import sys

import h5py
import numpy as np

import matplotlib.ticker

import report_runs
from report_figures import band, paper_hline, paper_points, paper_vline, plt, runs_line, savefig

ALPHA, A_TAU0, L_LAMBDA0, M = 0.9, 4.0, 2.5, 50
BETA = 0.5 * (1 + ALPHA)
TIMES = [0.13, 0.5, 1.0, 1.5, 2.0]
# Paper 000, text after Fig. 1 (Sec. V.A): s at the times of Fig. 2, IHS.
PAPER_S = {"equilibrium": [0.08, 0.4, 1.1, 2.1, 3.4], "delta_shell": [0.09, 0.5, 1.5, 2.8, 4.6]}
FIGDIR = "usf-inhomogeneous"  # under DOCDIR
# Paper 000, Sec. V.A: what its text states of Figs. 3 and 4.
PAPER_S_MAX_DN, PAPER_S_MAX_DT, PAPER_S_USF, PAPER_T_USF = 1.0, 0.15, 4.0, 2.2
PAPER_TS, PAPER_S_TS = 147.0, 50.0
PAPER_PXY, PAPER_N1, PAPER_S_STRESS = 0.33, 0.24, 40.0
INIT_LABEL = {"equilibrium": "Eq. 3.5", "delta_shell": "Eq. 3.6"}


def cases(f):
    """{label: group} of a sweep file (the root for a single case)."""
    if "cases" not in f:
        return {"": f}
    return {f["cases"][k].attrs["case"]: f["cases"][k] for k in sorted(f["cases"], key=int)}


def series(g, diag, name):
    d = g["diagnostics"][diag]
    t, s = d["time"][()], d["collisions_per_particle"][()]
    v = d[name][()]
    e = d[name + "_stderr"][()] if name + "_stderr" in d else np.full_like(v, np.nan)
    return t, s, v, e


def at(x, xs, ys):
    return float(np.interp(x, xs, ys)) if xs[0] <= x <= xs[-1] else float("nan")


def steady(g, diag, name, s_min, scale=1.0, batches=6):
    """Time average of the realization-averaged series over s/scale >= s_min, with the standard error
    of `batches` long batch means (each ~10 collisions per particle, longer than the correlation time
    of T in the steady USF; the host's 64-batch estimate, steady_stderr, is 5-7 times smaller here
    because its batches are shorter than that correlation time)."""
    _, s, v, _ = series(g, diag, name)
    x = v[(s / scale >= s_min) & np.isfinite(v)]
    if len(x) < 2 * batches:
        return float("nan"), float("nan")
    n = len(x) // batches
    means = np.array([x[k * n:(k + 1) * n].mean() for k in range(batches)])
    return float(x.mean()), float(means.std(ddof=1) / np.sqrt(batches))


def host_steady_error(g, diag, name):
    d = g["diagnostics"][diag]
    return float(d[name + ".steady_stderr"][()]) if name + ".steady_stderr" in d else float("nan")


def f3(x, d=3):
    return "n/a" if not np.isfinite(x) else f"{x:.{d}f}"


def pm(m, e, d=3):
    if not np.isfinite(m):
        return "n/a"
    return f"{m:.{d}f} ± {e:.{d}f}" if np.isfinite(e) else f"{m:.{d}f}"


# --- figures ---------------------------------------------------------------------------------


def s_series(g):
    """(t, s, standard error of s) from collision_count: accepted collisions / N over realizations."""
    d = g["diagnostics"]["collision_count"]
    n = float(g["system"].attrs["particles"])
    t, s = d["time"][()], d["collisions_per_particle"][()]
    e = d["collisions_stderr"][()] / n if "collisions_stderr" in d else np.full_like(s, np.nan)
    return t, s, e


def figure_1(T, S, docdir):
    """Paper's Fig. 1: s(t) (IHS) and s'(t) (EHS) against t/tau0 from Eq. 3.5, s'/s on the right axis;
    beside it the first 2.2 tau0 with the s the paper states at the times of Fig. 2."""
    fig, (ax, az) = plt.subplots(1, 2, figsize=(13, 4.6), gridspec_kw={"width_ratios": [1.35, 1]})
    ti, si, ei = s_series(S["case=IHS_equilibrium"])
    te, se, ee = s_series(S["case=EHS_equilibrium"])
    band(ax, ti, si, ei, color="C0", label="s(t), IHS")
    band(ax, te, se, ee, color="C0", linestyle="--", label="s′(t), EHS")
    paper_vline(ax, 8.0, label="paper: slopes constant for t/τ⁰ ≳ 8")
    ax.set_xlabel("t / τ⁰")
    ax.set_ylabel("collisions per particle s, s′")
    ax.set_xlim(0, min(ti[-1], te[-1]))
    ax.set_ylim(0, None)
    ar = ax.twinx()
    tt = ti[(ti > 0.3) & (ti <= te[-1])]
    sei, see = np.interp(tt, ti, si), np.interp(tt, te, se)
    r = see / sei
    re = r * np.hypot(np.interp(tt, ti, ei) / sei, np.interp(tt, te, ee) / see)
    band(ar, tt, r, re, color="C3", linewidth=0.9, label="s′/s (right axis)")
    paper_hline(ar, BETA, label=f"β = (1 + α)/2 = {BETA:g}")
    ar.set_ylim(0.88, 1.0)
    ar.set_ylabel("s′ / s", color="C3")
    ar.tick_params(axis="y", colors="C3")
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = ar.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, loc="upper left", fontsize=8)
    ax.set_title("Fig. 1: α = 0.9, aτ⁰ = 4, from Eq. 3.5 (steady run, 3 realizations)", fontsize=10)
    for label, g in T.items():
        model, init = (x.split("=")[1] for x in label.split(", "))
        t, s, e = s_series(g)
        band(az, t, s, e, color="C0" if init == "equilibrium" else "C2", linestyle="-" if model == "IHS" else "--",
             label=f"{'s' if model == 'IHS' else 's′'}, {model}, {INIT_LABEL[init]}")
    paper_points(az, TIMES, PAPER_S["equilibrium"], label="paper, IHS, Eq. 3.5")
    paper_points(az, TIMES, PAPER_S["delta_shell"], marker="s", label="paper, IHS, Eq. 3.6")
    az.set_xlabel("t / τ⁰")
    az.set_ylabel("collisions per particle s, s′")
    az.set_xlim(0, 2.2)
    az.set_ylim(0, None)
    az.legend(loc="upper left", fontsize=8)
    az.set_title("The first 2.2 τ⁰ (transient run) and the s the paper states", fontsize=10)
    fig.tight_layout()
    return savefig(fig, docdir, FIGDIR, "fig1_collisions")


def figure_2(T, docdir):
    """Paper's Fig. 2: u_x, n and T across the slab at the five times; IHS solid, EHS dashed, Eq. 3.5
    without symbols, Eq. 3.6 with; +- a realization standard error shaded; the USF profiles dotted."""
    u_half = 0.5 * A_TAU0 * L_LAMBDA0
    fig, axes = plt.subplots(3, len(TIMES), figsize=(17, 9.5), sharex=True, sharey="row")
    quantities = (("u_x", r"$u_x\,/\,(U/2)$"), ("n", r"$n\,/\,\bar{n}$"), ("T", r"$T\,/\,\bar{T}$"))
    for col, x in enumerate(TIMES):
        s_at = {}
        for label, g in T.items():
            model, init = (v.split("=")[1] for v in label.split(", "))
            d = g["diagnostics"]["profiles"]
            t = d["time"][()]
            r = int(np.argmin(np.abs(t - x)))
            y = d["bin_centre"][()] / L_LAMBDA0
            n, ne = d["n"][r], d["n_stderr"][r]
            tbar = np.nansum(n * d["T"][r]) / np.nansum(n)
            vals = {"u_x": (d["u_x"][r] / u_half, d["u_x_stderr"][r] / u_half), "n": (n, ne),
                    "T": (d["T"][r] / tbar, d["T_stderr"][r] / tbar)}
            if model == "IHS":
                s_at[init] = d["collisions_per_particle"][r]
            style = {"color": "C0" if init == "equilibrium" else "C1", "linestyle": "-" if model == "IHS" else "--",
                     "linewidth": 1.2}
            if init == "delta_shell":
                style.update(marker="o" if model == "IHS" else "s", markersize=3.5, markevery=4,
                             markerfacecolor="none" if model == "EHS" else None)
            for row, (q, _) in enumerate(quantities):
                band(axes[row, col], y, *vals[q], alpha=0.15,
                     label=f"{model}, {INIT_LABEL[init]}" if (row, col) == (0, 0) else None, **style)
        yy = np.array([-0.5, 0.5])
        axes[0, col].plot(yy, 2 * yy, color="0.5", linestyle=":", linewidth=1.2,
                          label=r"USF: $u_x = ay$, $n = \bar{n}$, $T = \bar{T}$" if col == 0 else None)
        axes[1, col].axhline(1, color="0.5", linestyle=":", linewidth=1.2)
        axes[2, col].axhline(1, color="0.5", linestyle=":", linewidth=1.2)
        axes[0, col].set_title(f"t/τ⁰ = {x:g}\ns = {s_at.get('equilibrium', np.nan):.2f} (paper ≈ {PAPER_S['equilibrium'][col]:g}), "
                               f"{s_at.get('delta_shell', np.nan):.2f} (≈ {PAPER_S['delta_shell'][col]:g})", fontsize=9)
        axes[2, col].set_xlabel("y / L")
    for row, (_, lab) in enumerate(quantities):
        axes[row, 0].set_ylabel(lab)
    axes[0, 0].set_xlim(-0.5, 0.5)
    axes[2, 0].set_ylim(0, None)
    fig.legend(*axes[0, 0].get_legend_handles_labels(), loc="lower center", ncol=5, fontsize=9,
               bbox_to_anchor=(0.5, -0.01))
    fig.suptitle("Fig. 2: profiles across the slab, α = 0.9, aτ⁰ = 4 (s: IHS from Eq. 3.5, from Eq. 3.6)", fontsize=11)
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    return savefig(fig, docdir, FIGDIR, "fig2_profiles")


def figure_3(T, S, docdir):
    """Paper's Fig. 3: u_x, n, T of the four central layers and of the three top layers against s
    (IHS solid, EHS dashed at s'/beta), from Eq. 3.5: the transient run (records every 40 steps) up to
    its end, then the steady run (every 160 steps) to s = 10."""
    u_half = 0.5 * A_TAU0 * L_LAMBDA0
    u_usf = A_TAU0 * (0.5 * L_LAMBDA0 - 1.5 * L_LAMBDA0 / M) / u_half
    fig, axes = plt.subplots(3, 1, figsize=(8, 10), sharex=True)
    for model, tl, sl in (("IHS", "model=IHS, initial=equilibrium", "case=IHS_equilibrium"),
                          ("EHS", "model=EHS, initial=equilibrium", "case=EHS_equilibrium")):
        scale = BETA if model == "EHS" else 1.0
        ls = "-" if model == "IHS" else "--"
        _, s1, _, _ = series(T[tl], "slab_averages", "T_bar")
        s_end = s1[-1] / scale
        for group, colour in (("centre", "C0"), ("top", "C3")):
            for row, q in enumerate(("u_x", "n", "T")):
                for g, part in ((T[tl], "transient"), (S[sl], "steady")):
                    _, s, v, e = series(g, "slab_averages", f"{group}_{q}")
                    _, _, tb, tbe = series(g, "slab_averages", "T_bar")
                    s = s / scale
                    if q == "u_x":
                        v, e = v / u_half, e / u_half
                    elif q == "T":
                        v, e = v / tb, e / tb  # the error of T_bar (0.1-1 % of it) is left out
                    keep = (s > 0) & ((s <= s_end) if part == "transient" else ((s > s_end) & (s <= 10.5)))
                    band(axes[row], s[keep], v[keep], e[keep], color=colour, linestyle=ls, linewidth=1.1, alpha=0.18,
                         label=(f"{'y ≈ 0 (4 central layers)' if group == 'centre' else 'y ≈ L/2 − 3δy/2 (3 top layers)'}, "
                                f"{model}{' at s′/β' if model == 'EHS' else ''}")
                         if row == 0 and part == "transient" else None)
    axes[0].axhline(0, color="0.5", linestyle=":", linewidth=1.2)
    axes[0].axhline(u_usf, color="0.5", linestyle=":", linewidth=1.2, label=r"USF: $u_x = 0$ and $a(L/2 - 3\delta y/2) = $" + f"{u_usf:.2f} U/2")
    axes[0].axhline(1.0, color="0.75", linestyle="--", linewidth=0.8, label="wall velocity U/2")
    for ax in axes[1:]:
        ax.axhline(1, color="0.5", linestyle=":", linewidth=1.2, label="USF: uniform" if ax is axes[1] else None)
    paper_vline(axes[1], PAPER_S_MAX_DN, label="paper: largest density difference, s ≈ 1")
    paper_vline(axes[2], PAPER_S_MAX_DT, label="paper: largest temperature difference, s ≈ 0.15")
    for ax in axes:
        paper_vline(ax, PAPER_S_USF, linestyle="--", label="paper: USF profiles reached, s ≈ 4" if ax is axes[0] else None)
    axes[0].set_ylabel(r"$u_x\,/\,(U/2)$")
    axes[1].set_ylabel(r"$n\,/\,\bar{n}$")
    axes[2].set_ylabel(r"$T\,/\,\bar{T}$")
    axes[2].set_xlabel("s (IHS), s′/β (EHS): collisions per particle")
    axes[2].set_xscale("log")
    axes[2].set_xlim(0.02, 10.5)
    axes[2].set_yscale("log")
    axes[2].set_yticks([0.3, 0.5, 1, 2, 3, 5])
    axes[2].yaxis.set_major_formatter(matplotlib.ticker.ScalarFormatter())
    axes[2].yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    axes[0].legend(fontsize=7.5, loc="center right")
    axes[1].legend(fontsize=7.5, loc="lower right")
    axes[2].legend(fontsize=7.5, loc="upper right")
    axes[0].set_title("Fig. 3: near y = 0 and y = L/2, α = 0.9, aτ⁰ = 4, from Eq. 3.5", fontsize=10)
    fig.tight_layout()
    return savefig(fig, docdir, FIGDIR, "fig3_groups")


def global_figure(curves, title, name, docdir):
    """Paper's Figs. 4 and 9: T_bar/T0 (top) and -P_xy/nT, (P_xx - P_yy)/nT (bottom) against s, with
    the steady values the paper states (dotted) at the s it states (open markers)."""
    fig, (at_, ap) = plt.subplots(2, 1, figsize=(8, 8), sharex=True, gridspec_kw={"height_ratios": [1, 1.15]})
    for label, g, diag, scale, ls in curves:
        names = {"slab_averages": ("T_bar", "minus_Pxy_over_nT", "Pxx_minus_Pyy_over_nT"),
                 "shear_rheology": ("temperature", "minus_Pxy_over_nT", "N1_over_nT")}[diag]
        for ax, k, colour, q in ((at_, 0, "C0", ""), (ap, 1, "C0", r"$-\bar{P}_{xy}/\bar{n}\bar{T}$, "),
                                (ap, 2, "C3", r"$(\bar{P}_{xx} - \bar{P}_{yy})/\bar{n}\bar{T}$, ")):
            _, s, v, e = series(g, diag, names[k])
            s = s / scale
            keep = s > 0
            band(ax, s[keep], v[keep], e[keep], color=colour, linestyle=ls, linewidth=1.1, alpha=0.2, label=q + label)
    paper_hline(at_, PAPER_TS)
    paper_points(at_, [PAPER_S_TS], [PAPER_TS], label=r"paper: $\bar{T}_s/T^0 \approx$" + f" {PAPER_TS:g} at s ≈ {PAPER_S_TS:g}")
    paper_hline(ap, PAPER_PXY)
    paper_hline(ap, PAPER_N1)
    paper_points(ap, [PAPER_S_STRESS] * 2, [PAPER_PXY, PAPER_N1],
                 label=f"paper: {PAPER_PXY:g} and {PAPER_N1:g} after s ≈ {PAPER_S_STRESS:g}")
    for ax in (at_, ap):
        ax.axvspan(60, 130, color="0.9", zorder=0, label="steady average of the report (s ≥ 60)" if ax is at_ else None)
    at_.set_ylabel(r"$\bar{T}\,/\,T^0$")
    at_.set_ylim(0, None)
    ap.set_ylabel(r"$-\bar{P}_{xy}/\bar{n}\bar{T}$,  $(\bar{P}_{xx} - \bar{P}_{yy})/\bar{n}\bar{T}$")
    ap.set_ylim(0, 1.15 * ap.get_ylim()[1])  # room for the legend above the curves
    ap.set_xscale("log")
    ap.set_xlim(0.05, 130)
    ap.set_xlabel("s (IHS), s′/β (EHS): collisions per particle")
    at_.legend(fontsize=8, loc="upper left")
    ap.legend(fontsize=7.5, loc="upper right", ncol=1)
    at_.set_title(title, fontsize=10)
    fig.tight_layout()
    return savefig(fig, docdir, FIGDIR, name)


def select_runs(places):
    """The paths of scripts/validate-usf-inhomogeneous's five runs among the outputs in places, by their
    provenance, in the order of the report's header: transient, steady, homogeneous IHS and EHS, distinct."""
    runs = report_runs.index(*places)
    pairs = "run.candidate_pairs"
    found = [runs.one(config="usf_inhomogeneous_transient"), runs.one(config="usf_inhomogeneous_steady", unset=(pairs,)),
             runs.one(config="usf_ihs_alpha0.9_shear4"), runs.one(config="usf_ehs_alpha0.9_shear4"),
             runs.one(config="usf_inhomogeneous_steady", set={pairs: "distinct"})]
    names = ("usf_inhomogeneous_transient", "usf_inhomogeneous_steady (without run.candidate_pairs)",
             "usf_ihs_alpha0.9_shear4", "usf_ehs_alpha0.9_shear4", "usf_inhomogeneous_steady with run.candidate_pairs=distinct")
    absent = [f"configs/{n}" for n, o in zip(names, found) if o is None]
    if absent:
        sys.exit(f"usf_inhomogeneous_report.py: no output of {', '.join(absent)} among {', '.join(places)}")
    return [o.path for o in found]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("outputs", nargs="+", help="folders of outputs (searched recursively) or output files")
    ap.add_argument("--docdir", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "docs", "validation"))
    args = ap.parse_args()
    docdir = args.docdir
    paths = select_runs(args.outputs)
    tr, st, hi, he = (h5py.File(p, "r") for p in paths[:4])
    dc = cases(h5py.File(paths[4], "r"))
    T = cases(tr)
    S = cases(st)
    out = []
    w = out.append
    w("# Inhomogeneous uniform shear flow (paper 000, Sec. IV.A): validation")
    w("")
    w("Every path named in this document is in the source tree. Generated by `scripts/validate-usf-inhomogeneous` (which runs `configs/usf_inhomogeneous_transient.yaml`,")
    w("`configs/usf_inhomogeneous_steady.yaml` and the homogeneous `configs/usf_{ihs,ehs}_alpha0.9_shear4.yaml`")
    w("with three realizations to s = 120) and `scripts/usf_inhomogeneous_report.py`. Paper 000 is Astillero &")
    w("Santos, see [docs/references.md](../references.md). " + runs_line(*paths) + ".")
    w("")
    w(f"Setup, as the paper's Sec. IV.A: α = {ALPHA}, aτ⁰ = {A_TAU0:g}, Lees–Edwards boundaries at y = ±L/2 with")
    w(f"L = {L_LAMBDA0:g}λ⁰ (U = aL), M = {M} layers (δy = 0.05λ⁰), N = 10⁴, δt = 10⁻³τ⁰√(T⁰/T̄), moments every 4")
    w("steps, three realizations (values below are their means; ± is the standard error over realizations, or")
    w("for steady values the batch-means error of the time average). IHS: inelastic hard spheres; EHS: elastic")
    w("spheres with the collision rate × β = 0.95 and the local drag of Eq. 4.12 per layer. The candidate")
    w("count of a layer is built on N_I²/2 pairs as Eq. 4.13 writes it (`run.candidate_pairs: squared`); one")
    w("control run uses gdsmc's default N_I(N_I − 1)/2. Initial states:")
    w("'equilibrium' is Eq. 3.5 (uniform, at rest), 'delta_shell' is Eqs. 3.6–3.8.")
    w("")

    # --- Fig. 1 and the s values of the text -------------------------------------------------
    w("## Collisions per particle s(t) (Fig. 1 and the text of Sec. V.A)")
    w("")
    w("| case | " + " | ".join(f"t/τ⁰ = {t:g}" for t in TIMES) + " |")
    w("|---|" + "---|" * len(TIMES))
    for label, g in T.items():
        t, s, _, _ = series(g, "collision_count", "collisions_per_particle")
        w(f"| {label} | " + " | ".join(f3(at(x, t, s), 3) for x in TIMES) + " |")
    for init, vals in PAPER_S.items():
        w(f"| paper, IHS, {init} | " + " | ".join(f"≈ {v:g}" for v in vals) + " |")
    w("")
    w("s′/s (EHS over IHS, the same initial state and times; the paper: it fluctuates about β = 0.95 up to")
    w("t ≈ 4τ⁰ and stays very close to 0.95 thereafter):")
    w("")
    w("| initial state | " + " | ".join(f"t/τ⁰ = {t:g}" for t in TIMES + [4.0, 8.0]) + " |")
    w("|---|" + "---|" * (len(TIMES) + 2))
    for init in ("equilibrium", "delta_shell"):
        ti, si, _, _ = series(T[f"model=IHS, initial={init}"], "collision_count", "collisions_per_particle")
        te, se, _, _ = series(T[f"model=EHS, initial={init}"], "collision_count", "collisions_per_particle")
        row = [at(x, te, se) / at(x, ti, si) for x in TIMES]
        if init == "equilibrium":
            ti2, si2, _, _ = series(S["case=IHS_equilibrium"], "collision_count", "collisions_per_particle")
            te2, se2, _, _ = series(S["case=EHS_equilibrium"], "collision_count", "collisions_per_particle")
            row += [at(x, te2, se2) / at(x, ti2, si2) for x in (4.0, 8.0)]
        else:
            row += [float("nan")] * 2
        w(f"| {init} | " + " | ".join(f3(v, 3) for v in row) + " |")
    w("")
    ti, si, _, _ = series(S["case=IHS_equilibrium"], "collision_count", "collisions_per_particle")
    slope = np.gradient(si, ti)
    w("Slope ds/dt [1/τ⁰] of the IHS run from Eq. 3.5 (the paper: it increases until it becomes constant for")
    w("t/τ⁰ ≳ 8): " + ", ".join(f"{at(x, ti, slope):.2f} at t/τ⁰ = {x:g}" for x in (2, 4, 6, 8, 10, 12, 16) if x <= ti[-1]) + ".")
    w("")
    w("Fig. 1, left: s(t) and s′(t) of the steady runs from Eq. 3.5 against t/τ⁰, and s′/s on the right axis")
    w("(β = 0.95 dotted; dash-dot: t/τ⁰ = 8, from where the paper has constant slopes). Right: the first")
    w("2.2τ⁰ of the transient runs, the data of the first table, with the paper's s at the times of Fig. 2 as")
    w("open markers. Shaded here and in every figure below: ± one standard error over the three realizations")
    w("(for s′/s propagated from those of s and s′).")
    w("")
    w(figure_1(T, S, docdir))
    w("")

    # --- Fig. 2 profiles -----------------------------------------------------------------------
    w("## Profiles (Fig. 2)")
    w("")
    w("u_x in units of U/2 = aL/2, n/n̄ and T/T̄ at five positions (layer centres y/L = −0.49, −0.25, 0.01,")
    w("0.25, 0.49), at the times of Fig. 2 (each value is the window mean of the 10 steps before the record")
    w("nearest to that time, averaged over the realizations).")
    w("")
    layers = [0, 12, 25, 37, 49]
    u_half = 0.5 * A_TAU0 * L_LAMBDA0  # U/2 in units of lambda0/tau0 = sqrt(2 T0/m)
    for label, g in T.items():
        d = g["diagnostics"]["profiles"]
        t = d["time"][()]
        y = d["bin_centre"][()] / L_LAMBDA0
        w(f"**{label}**")
        w("")
        w("| t/τ⁰ | quantity | " + " | ".join(f"y/L = {y[k]:+.2f}" for k in layers) + " |")
        w("|---|---|" + "---|" * len(layers))
        for x in TIMES:
            r = int(np.argmin(np.abs(t - x)))
            n = d["n"][r]
            Tp = d["T"][r]
            tbar = np.nansum(n * Tp) / np.nansum(n)
            w(f"| {t[r]:.3f} | u_x/(U/2) | " + " | ".join(f3(d['u_x'][r][k] / u_half, 2) for k in layers) + " |")
            w(f"| | n/n̄ | " + " | ".join(f3(n[k], 2) for k in layers) + " |")
            w(f"| | T/T̄ | " + " | ".join(f3(Tp[k] / tbar, 2) for k in layers) + " |")
        w("")
    w("What the paper states of Fig. 2, checked on these tables: at t/τ⁰ = 0.13 the flow velocity is the")
    w("initial one except in the layers next to the boundaries, those layers are much hotter than the bulk,")
    w("and the density is practically unchanged; then the velocity profile stretches towards u_x = ay, the")
    w("layers next to the boundaries are first depopulated, and density and temperature become uniform.")
    w("")
    w("Fig. 2, from the same records as the tables (all 50 layers): IHS solid, EHS dashed, Eq. 3.5 without")
    w("symbols, Eq. 3.6 with; the USF profiles dotted; above each column the s of this run and of the paper.")
    w("")
    w(figure_2(T, docdir))
    w("")

    # --- Fig. 3 layer groups -------------------------------------------------------------------
    w("## Evolution near y = 0 and near y = L/2 (Fig. 3, IHS and EHS from Eq. 3.5)")
    w("")
    w("The centre group is the four central layers (|y| ≤ 2δy), the top group the three top layers")
    w("(y ≥ L/2 − 3δy), as in the paper. The USF values are u_x = 0 (centre) and a(L/2 − 1.5δy) = 0.94·U/2 (top),")
    w("n = n̄ and T = T̄.")
    w("")
    w("| case | s at the largest density difference (paper ≈ 1) | s at the largest temperature difference (paper ≈ 0.15) | first s from which the groups stay within 5 % of the USF values (paper: s ≈ 4, t/τ⁰ ≈ 2.2) |")
    w("|---|---|---|---|")
    def smooth(x, k=5):
        return np.convolve(x, np.ones(k) / k, mode="same")

    for label, steady_label in (("model=IHS, initial=equilibrium", "case=IHS_equilibrium"),
                                ("model=EHS, initial=equilibrium", "case=EHS_equilibrium")):
        g = T[label]
        t, s, top_n, _ = series(g, "slab_averages", "top_n")
        _, _, centre_n, _ = series(g, "slab_averages", "centre_n")
        _, _, top_T, _ = series(g, "slab_averages", "top_T")
        _, _, centre_T, _ = series(g, "slab_averages", "centre_T")
        _, _, tbar, _ = series(g, "slab_averages", "T_bar")
        scale = BETA if "EHS" in label else 1.0
        s = s / scale
        dn = smooth(np.abs(top_n - centre_n))
        dT = smooth(np.abs(top_T - centre_T) / tbar)
        # Settling, on the longer steady run (records every 160 steps): every group value within 5 %
        # of its USF value or within 3 standard errors over the realizations, from then on.
        h = S[steady_label]
        t2, s2, tu, tu_e = series(h, "slab_averages", "top_u_x")
        _, _, tn, tn_e = series(h, "slab_averages", "top_n")
        _, _, cn, cn_e = series(h, "slab_averages", "centre_n")
        _, _, tT, tT_e = series(h, "slab_averages", "top_T")
        _, _, cT, cT_e = series(h, "slab_averages", "centre_T")
        s2 = s2 / scale
        u_usf = A_TAU0 * (0.5 * L_LAMBDA0 - 1.5 * L_LAMBDA0 / M)

        def close(v, ref):
            return np.abs(smooth(v) - smooth(ref)) <= 0.05 * np.abs(smooth(ref))

        # Up to s = 10 only: later the thermal noise of a three-layer mean (T grows 150-fold while
        # u_x stays a y) exceeds 5 % of u_x.
        window = s2 <= 10
        ok = (close(tu, np.full_like(tu, u_usf)) & close(tn, cn) & close(tT, cT))[window]
        s2, t2 = s2[window], t2[window]
        table = [(x, at(x, s2, smooth(tu)[window]) / u_usf, at(x, s2, smooth(tn / cn)[window]),
                   at(x, s2, smooth(tT / cT)[window])) for x in (0.5, 1, 2, 3, 4, 6, 8)]
        if "IHS" in label:
            groups = table
        settle_text = "not before s = 10"
        for k in range(len(ok)):
            if ok[k:].all():
                settle_text = f"s = {s2[k]:.1f} (t/τ⁰ = {t2[k]:.2f})"
                break
        w(f"| {label}{' (s′/β)' if 'EHS' in label else ''} | {s[int(np.argmax(dn))]:.2f} | {s[int(np.argmax(dT))]:.2f} | {settle_text} |")
    w("")
    w("Top group against centre group (5-record running means of the steady run, IHS from Eq. 3.5); each")
    w("ratio is 1 in the USF:")
    w("")
    w("| s | " + " | ".join(f"{g[0]:g}" for g in groups) + " |")
    w("|---|" + "---|" * len(groups))
    w("| top u_x / a(L/2 − 1.5δy) | " + " | ".join(f3(g[1], 2) for g in groups) + " |")
    w("| top n / centre n | " + " | ".join(f3(g[2], 2) for g in groups) + " |")
    w("| top T / centre T | " + " | ".join(f3(g[3], 2) for g in groups) + " |")
    w("")
    w("(The largest differences are taken on a 5-record running mean of the transient run, records every")
    w("40 steps; the settling test uses a 5-record running mean of the steady run, records every 160 steps,")
    w("and asks every group value to stay within 5 % of its USF value up to s = 10.)")
    w("")
    w("Fig. 3: the group values, u_x in units of U/2 = aL/2, n/n̄ and T/T̄ (T/T̄ on a logarithmic scale), against")
    w("s (IHS, solid) and s′/β (EHS, dashed) on a logarithmic axis: the transient run up to its end at t = 2.2τ⁰")
    w("(s ≈ 3.9), then the steady run to s = 10.")
    w("Dotted: the USF values; dash-dot: the s the paper states for the largest density and temperature")
    w("differences; dashed: s ≈ 4, where the paper has the USF profiles reached.")
    w("")
    w(figure_3(T, S, docdir))
    w("")

    # --- Figs. 4 and 9 -------------------------------------------------------------------------
    w("## Global quantities against s (Figs. 4 and 9)")
    w("")
    w("T̄/T⁰ (Eq. 4.8), −P̄_xy/n̄T̄ and (P̄_xx − P̄_yy)/n̄T̄ (Eq. 4.9). EHS is read at s′/β, as in the paper.")
    w("The homogeneous rows are the Lagrangian-frame engine from Eq. 3.12 (same α, a, N, δt, realizations).")
    w("")
    S_POINTS = [1, 2, 4, 10, 20, 40, 60, 100]
    rows = [("inhomogeneous IHS, Eq. 3.5", S["case=IHS_equilibrium"], "slab_averages", 1.0),
            ("inhomogeneous IHS, Eq. 3.6", S["case=IHS_delta_shell"], "slab_averages", 1.0),
            ("inhomogeneous EHS, Eq. 3.5", S["case=EHS_equilibrium"], "slab_averages", BETA),
            ("inhomogeneous IHS, Eq. 3.5, N_I(N_I−1)/2 pairs", dc["case=IHS_equilibrium"], "slab_averages", 1.0),
            ("homogeneous IHS, Eq. 3.12", hi, "shear_rheology", 1.0),
            ("homogeneous EHS, Eq. 3.12", he, "shear_rheology", BETA)]
    names = {"slab_averages": ("T_bar", "minus_Pxy_over_nT", "Pxx_minus_Pyy_over_nT"),
             "shear_rheology": ("temperature", "minus_Pxy_over_nT", "N1_over_nT")}
    for title, k in (("T̄/T⁰", 0), ("−P̄_xy/n̄T̄", 1), ("(P̄_xx − P̄_yy)/n̄T̄", 2)):
        w(f"**{title}**")
        w("")
        w("| run | " + " | ".join(f"s = {x}" for x in S_POINTS) + " |")
        w("|---|" + "---|" * len(S_POINTS))
        for label, g, diag, scale in rows:
            _, s, v, _ = series(g, diag, names[diag][k])
            s = s / scale
            w(f"| {label} | " + " | ".join(f3(at(x, s, v), 3 if k else 2) for x in S_POINTS) + " |")
        w("")
    w("### Steady state (time averages over s ≥ 60; EHS over s′/β ≥ 60)")
    w("")
    w("± is the standard error of 6 batch means of the realization-averaged series (each batch about 10")
    w("collisions per particle). The host's own `steady_stderr` of T̄ is given in brackets (gdsmc ≥ 0.2")
    w("derives it from the scatter between the realizations' own steady means).")
    w("")
    w("| run | T̄_s/T⁰ | −P̄_xy/n̄T̄ | (P̄_xx − P̄_yy)/n̄T̄ |")
    w("|---|---|---|---|")
    for label, g, diag, scale in rows:
        vals = [steady(g, diag, n, 60, scale) for n in names[diag]]
        host = host_steady_error(g, diag, names[diag][0])
        w(f"| {label} | {pm(*vals[0], 1)} [{host:.1f}] | {pm(*vals[1], 4)} | {pm(*vals[2], 4)} |")
    w("| paper 000, inhomogeneous IHS (Sec. V.A) | ≈ 147 (at s ≈ 50, t/τ⁰ ≈ 9.8) | ≈ 0.33 | ≈ 0.24 (after s ≈ 40) |")
    w("| our earlier single homogeneous IHS run (docs/validation/usf.md; its error was 3.5 times too small, see README.md: 34 runs give 148.1 ± 0.1) | 149.3 ± 0.2 | 0.3312–0.3327 | 0.237–0.241 |")
    w("")
    _, s_ihs, tb, _ = series(S["case=IHS_equilibrium"], "slab_averages", "T_bar")
    t_ihs = S["case=IHS_equilibrium"]["diagnostics"]["slab_averages"]["time"][()]
    ts, _ = steady(S["case=IHS_equilibrium"], "slab_averages", "T_bar", 60)
    k = next((i for i in range(len(tb)) if np.all(np.abs(tb[i:] / ts - 1) < 0.02)), None)
    if k is not None:
        w(f"T̄ of the IHS run from Eq. 3.5 stays within 2 % of its steady value from s = {s_ihs[k]:.1f} (t/τ⁰ = {t_ihs[k]:.1f});")
        w("the paper: T̄ reaches its stationary value at s ≈ 50 (t/τ⁰ ≈ 9.8).")
        w("")
    w("### Figs. 4 and 9")
    w("")
    w("The tables' data, against s on a logarithmic axis (the kinetic stage at s ≲ 1 and the approach to the")
    w("steady state both show). Dotted lines and open markers: the steady values the paper states and the s at")
    w("which it states them; shaded grey: the window of the steady averages above.")
    w("")
    w("Fig. 4, IHS (solid) and EHS at s′/β (dashed), inhomogeneous, from Eq. 3.5:")
    w("")
    w(global_figure([("IHS", S["case=IHS_equilibrium"], "slab_averages", 1.0, "-"),
                     ("EHS", S["case=EHS_equilibrium"], "slab_averages", BETA, "--")],
                    "Fig. 4: inhomogeneous USF, α = 0.9, aτ⁰ = 4, from Eq. 3.5", "fig4_global", docdir))
    w("")
    w("Fig. 9, IHS: homogeneous from Eq. 3.12 (solid), inhomogeneous from Eq. 3.5 (dashed) and from Eq. 3.6")
    w("(dash-dot):")
    w("")
    w(global_figure([("homogeneous, Eq. 3.12", hi, "shear_rheology", 1.0, "-"),
                     ("inhomogeneous, Eq. 3.5", S["case=IHS_equilibrium"], "slab_averages", 1.0, "--"),
                     ("inhomogeneous, Eq. 3.6", S["case=IHS_delta_shell"], "slab_averages", 1.0, "-.")],
                    "Fig. 9: IHS, α = 0.9, aτ⁰ = 4, homogeneous and inhomogeneous", "fig9_global", docdir))
    w("")

    # --- energy balance and majorant -------------------------------------------------------------
    w("## Bookkeeping")
    w("")
    w("| run | energy balance residual (E − E⁰ − Σ stages) / E | candidates above the layer majorant |")
    w("|---|---|---|")
    for label, g in S.items():
        d = g["diagnostics"]
        res = d["energy_balance"]["final_relative_residual"][()] if "final_relative_residual" in d["energy_balance"] else float("nan")
        ex = d["collision_count"]["majorant_exceeded"][()][-1]
        cand = d["collision_count"]["collisions"][()][-1] / max(d["collision_count"]["acceptance_ratio"][()][-1], 1e-300)
        w(f"| {label} | {res:.1e} | {ex:.0f} of {cand:.3g} ({ex / cand:.1e}) |")
    w("")
    print("\n".join(out))


if __name__ == "__main__":
    main()
