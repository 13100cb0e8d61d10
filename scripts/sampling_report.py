#!/usr/bin/python3
"""docs/validation/sampling.md from the runs of scripts/validate-sampling (issue 29, item 1): the
shear viscosity of elastic hard spheres and the elastic heat-flux anchor kappa' against the time
step, sampled after each step (after_step) and on both sides of the collision stage (bracketed),
and the plane Fourier flow's conductivity beside Chapman-Enskog's (written by profiles, fourier_law).

Usage: sampling_report.py OUTDIR > docs/validation/sampling.md
The runs are found in OUTDIR by their provenance (scripts/report_runs.py), whatever their file names:
configs/usf_elastic_viscosity_dt.yaml, configs/heat_flux_anchor_dt.yaml swept over dt and sampling,
and every output of configs/fourier_elastic.yaml. Computes no physics: every value and theory is
read from the outputs.
"""
import sys

import h5py
import numpy as np

import report_runs
from heat_flux_report import weighted_fit
from report_figures import runs_line


def cases(path, group, value):
    """{(dt, sampling): (mean, stderr, case group)} of the scalar `value` (its _mean and
    _standard_error) of diagnostic `group`, from a sweep over dt and sampling."""
    out = {}
    with h5py.File(path, "r") as f:
        for k in f["cases"]:
            c = f["cases"][k]
            dt = float(c.attrs["sweep.dt"])
            sampling = c.attrs["sweep.sampling"]
            sampling = sampling.decode() if isinstance(sampling, bytes) else str(sampling)
            g = c["diagnostics"][group]
            theory = {n: float(g[n][()]) for n in ("eta_star_chapman_enskog", "eta_star_thermostatted_bgk", "a_star_mean")
                      if n in g}
            out[(dt, sampling)] = (float(g[value + "_mean"][()]), float(g[value + "_standard_error"][()]), theory)
    return out


# Half-widths of the central windows of the plane Fourier flow, λ⁰.
FOURIER_WINDOWS = (1.5, 2.5)
# What profiles writes for each window (fourier_law: true, profiles 1.4.0 on): κ/κ_CE and its own error.
FOURIER_RATIO = "fourier_conductivity_over_chapman_enskog"
# The pipelines' time steps [τ⁰], at which the reports state the remaining bias.
DEFAULT_STEPS = (0.04, 0.08)
# The straight-line fits take the time steps up to the largest of them; a parabola takes them all.
LINE_MAX_DT = max(DEFAULT_STEPS)


def dt_table(w, data, unit_name, reference=None, reference_name=""):
    dts = sorted({k[0] for k in data})
    head = f"| δt [τ⁰] | {unit_name}, after_step | {unit_name}, bracketed | bracketed − after_step |"
    if reference is not None:
        head += f" bracketed − {reference_name} in errors |"
    w(head)
    w("|" + "---|" * (head.count("|") - 1))
    for dt in dts:
        a, b = data.get((dt, "after_step")), data.get((dt, "bracketed"))
        row = [f"{dt:g}"]
        row += [f"{v[0]:.4f} ± {v[1]:.4f}" if v else "–" for v in (a, b)]
        row.append(f"{b[0] - a[0]:+.4f}" if a and b else "–")
        if reference is not None:
            row.append(f"{(b[0] - reference) / b[1]:+.1f}" if b else "–")
        w("| " + " | ".join(row) + " |")
    w("")
    both = [dt for dt in dts if (dt, "after_step") in data and (dt, "bracketed") in data]
    if both:
        x = np.array(both)
        diff = np.array([data[(dt, "bracketed")][0] - data[(dt, "after_step")][0] for dt in both])
        w(f"- bracketed − after_step, a straight line through 0 (the same runs sampled both ways): "
          f"{(x * diff).sum() / (x * x).sum():+.3f} per τ⁰; largest departure from it "
          f"{np.abs(diff - x * (x * diff).sum() / (x * x).sum()).max():.4f}.")
    for s in ("after_step", "bracketed"):
        pts = [(dt, *data[(dt, s)][:2]) for dt in dts if (dt, s) in data]
        small = [p for p in pts if p[0] <= LINE_MAX_DT]
        if len(small) >= 3:
            x, y, e = (np.array(v) for v in zip(*small))
            c, cov, chi2 = weighted_fit(np.vstack([np.ones_like(x), x]).T, y, e)
            ce, dof = np.sqrt(np.diag(cov)), len(x) - 2
            w(f"- {s}: straight line in δt ≤ {LINE_MAX_DT:g} τ⁰: {c[0]:.4f} ± {ce[0]:.4f} at δt → 0, slope "
              f"{c[1]:+.3f} ± {ce[1]:.3f} per τ⁰ (χ² = {chi2:.2f} for {dof} degrees of freedom).")
        if len(pts) >= 5 and len(small) < len(pts):
            x, y, e = (np.array(v) for v in zip(*pts))
            c, cov, chi2 = weighted_fit(np.vstack([np.ones_like(x), x, x * x]).T, y, e)
            ce, dof = np.sqrt(np.diag(cov)), len(x) - 3
            w(f"- {s}: parabola in δt ≤ {x.max():g} τ⁰: {c[0]:.4f} ± {ce[0]:.4f} at δt → 0, "
              f"{c[1]:+.3f} ± {ce[1]:.3f} δt {c[2]:+.2f} ± {ce[2]:.2f} δt² (δt in τ⁰; χ² = {chi2:.2f} for {dof} "
              f"degrees of freedom); the bias it gives at δt = {' and '.join(f'{d:g}' for d in DEFAULT_STEPS)} τ⁰: "
              + ", ".join(f"{c[1] * d + c[2] * d * d:+.4f} ± {np.sqrt(np.array([d, d * d]) @ cov[1:, 1:] @ np.array([d, d * d])):.4f}"
                          for d in DEFAULT_STEPS) + ".")
    pts = [(dt, *data[(dt, "bracketed")][:2]) for dt in dts if (dt, "bracketed") in data]
    if reference is not None and len(pts) >= 3:
        # The bracketed bias as pure O(dt^2) about the theory: the one-parameter fit c dt^2.
        x, y, e = (np.array(v) for v in zip(*pts))
        c, cov, chi2 = weighted_fit((x * x)[:, None], y - reference, e)
        ce = np.sqrt(cov[0, 0])
        top = max(DEFAULT_STEPS)
        w(f"- bracketed − {reference_name} as c δt² alone: c = {c[0]:+.3f} ± {ce:.3f} per τ⁰² (χ² = {chi2:.2f} for "
          f"{len(x) - 1} degrees of freedom): at δt = {' and '.join(f'{d:g}' for d in DEFAULT_STEPS)} τ⁰ a bias of "
          + " and ".join(f"{c[0] * d * d:+.5f} ± {ce * d * d:.5f}" for d in DEFAULT_STEPS)
          + f", at most {(abs(c[0]) + 2 * ce) * top * top:.4f} at {top:g} τ⁰ (two errors).")
    w("")


def slab_width(case):
    """L [λ⁰] of a slab case, from the system it records."""
    g = case.open()
    try:
        a = g["system"].attrs
        return round(float(a["box_y"]) / float(a["mean_free_path0"]), 6)
    finally:
        g.file.close()


def fourier_rows(fourier):
    """Per (L, sampling, window half-width): κ/κ_CE as profiles wrote it (the realizations' mean and its
    standard error, their scatter, the mean of the single runs' own errors, their number, T at the centre),
    or None where the output predates profiles 1.4.0 (no fourier_law)."""
    rows = []
    for o in fourier:
        for c in o.cases:
            label = c.sweep.get("sampling", "bracketed")
            g = c.open()
            try:
                p = g["diagnostics/profiles"]
                for half in FOURIER_WINDOWS:
                    if FOURIER_RATIO not in p:
                        rows.append((slab_width(c), label, half, None))
                        continue
                    i = int(np.argmin(np.abs(p["fourier_window"][:] - 2 * half)))
                    K = int(p.attrs.get("realizations", 1))
                    se = float(p[FOURIER_RATIO + "_stderr"][i]) if K > 1 else float("nan")
                    rows.append((slab_width(c), label, half, (float(p[FOURIER_RATIO][i]), se, se * np.sqrt(K),
                                                              float(p[FOURIER_RATIO + "_error"][i]), K,
                                                              float(p["fourier_centre_temperature"][i]))))
            finally:
                g.file.close()
    return sorted(rows, key=lambda r: r[0])


def main():
    runs = report_runs.index(sys.argv[1])
    usf = runs.one(config="usf_elastic_viscosity_dt")
    hf = runs.one(config="heat_flux_anchor_dt", axes=("dt", "sampling"))
    fourier = runs.find(config="fourier_elastic")
    out = []
    w = out.append
    w("# Validation: sampling without the time step's O(δt) bias")
    w("")
    w("Every path named in this document is in the source tree. Generated by `scripts/validate-sampling` (`scripts/sampling_report.py`); do not edit by hand.")
    present = [o.path for o in [usf, hf] + list(fourier) if o]
    if present:
        w(f"Runs: {runs_line(*present)}.")
    w("")
    w("A step is a splitting: free flight and the forcings, then the collisions. A moment that the flow or a force")
    w("builds and the collisions relax (a shear stress, a heat flux) is a sawtooth over the step. Sampled after the")
    w("step (`run.sampling: after_step`, the rule before SDK 6.1) it is too small by the fraction ν δt/2 (ν its")
    w("relaxation rate: p/η ≈ 0.9/τ⁰ for the shear stress of hard spheres at T⁰); sampled before the collisions it")
    w("is as much too large. `run.sampling: bracketed`, the default, takes both samples at t + δt in every diagnostic")
    w("that supports it and averages them, which leaves O(δt²). Each time step below is run twice from the same seed")
    w("(the sampling rule never changes the dynamics), so the difference between the two columns is the bias of the")
    w("after-step sample itself, with little noise.")
    w("")
    w("## Shear viscosity of elastic hard spheres (homogeneous USF at fixed temperature)")
    w("")
    w("`configs/usf_elastic_viscosity_dt.yaml`: a τ⁰ = 0.04513, energy_momentum_thermostat after the collisions,")
    w("N = 2·10⁵, 400 τ⁰ averaged from 40 τ⁰, a sample every 0.08 τ⁰ (every step from δt = 0.08 τ⁰ on; the steps up to")
    w("0.32 τ⁰, 0.35 collisions per particle per step, make the O(δt²) term measurable). η* = −(P_xy/nT)/a* in the unit of paper 000's")
    w("τ_η (Eq. 2.18, with 1.016), so Chapman–Enskog's 1.016034 η₀ is η* = 1.000033; the thermostat thins it by")
    w("1 − 4a*²/3 + … (Grad/BGK, `eta_star_thermostatted_bgk`, written by `shear_rheology`).")
    w("")
    if not usf:
        w("*(no output: run `scripts/validate-sampling`)*")
    else:
        data = cases(usf.path, "shear_rheology", "eta_star")
        theory = next(iter(data.values()))[2]
        ref = theory["eta_star_thermostatted_bgk"]
        w(f"Theory at the measured a* = {theory['a_star_mean']:.4f}: η* = {theory['eta_star_chapman_enskog']:.6f} "
          f"(Chapman–Enskog, a* → 0), {ref:.6f} with the thermostat's thinning.")
        w("")
        dt_table(w, data, "η*", ref, "theory")
        w("In the issue's unit (η/η₀ with η₀ the first-Sonine viscosity, η/η₀ = 1.016 η*), at the pipelines' steps:")
        w("")
        for dt in DEFAULT_STEPS:
            for s in ("after_step", "bracketed"):
                if (dt, s) in data:
                    m, e, _ = data[(dt, s)]
                    w(f"- δt = {dt:g} τ⁰, {s}: η/η₀ = {1.016 * m:.4f} ± {1.016 * e:.4f}; theory {1.016 * ref:.4f} "
                      f"(difference {100 * (m / ref - 1):+.2f} %, {(m - ref) / e:+.1f} errors).")
        w("")
    w("## Heat flux: the elastic anchor κ′/κ₀ of paper 001")
    w("")
    w("`configs/heat_flux_anchor_dt.yaml` shortened to 1000 τ per time step (N = 2·10⁴, ε* = 0.05, α = 1), each")
    w("time step with both rules. The after-step sample of q_x follows the force and the thermostat and precedes")
    w("the next step's collisions, so it sits at the top of the sawtooth: κ′ too large by about ν_q δt/2")
    w("(the long runs of `docs/validation/heat-flux-anchor.md`, δt = 0.003–0.03 τ over 5000 τ each, measured a slope")
    w("of +0.32 ± 0.10 per τ sampled after the step on 2026-11-23, and +0.08 ± 0.11 sampled bracketed on 2026-11-27).")
    w("Two time steps of 1000 τ cannot resolve a slope of that size in κ′ itself; the difference of the two rules on")
    w("the same runs can.")
    w("")
    if not hf:
        w("*(no output: run `scripts/validate-sampling`)*")
    else:
        dt_table(w, cases(hf.path, "heat_flux", "conductivity_over_kappa0"), "κ′/κ₀")
    w("## Heat flux: plane Fourier flow of elastic hard spheres")
    w("")
    w("`configs/fourier_elastic.yaml` (diffuse walls at 0.9 and 1.1 T⁰, L = 10 λ⁰, 80 layers, N = 2·10⁵, δt = 0.05 τ⁰,")
    w("600 τ⁰ averaged from 150 τ⁰, 6 realizations), sampled both ways from the same seeds. κ = −q_y/(dT/dy) in the central 3 λ⁰ (q_y the")
    w("mean of its bins, dT/dy a straight line through their T), over the converged Chapman–Enskog conductivity")
    w("1.025218 κ₀(T), κ₀ = (75/64)√(T/πm)/σ² (001 Eq. 2.47) at the mean T of those bins: `profiles` writes both")
    w("(`fourier_law: true`, from the moments pooled over the steady window of each realization). Here q_y is built by")
    w("the streaming and relaxed by the collisions, so the after-step sample sits at the bottom of the sawtooth.")
    w("")
    if not fourier:
        w("*(no output: run `scripts/validate-sampling`)*")
    else:
        w("| L [λ⁰] | sampling | window [λ⁰] | κ/κ_CE, mean of the realizations | scatter of the realizations "
          "(standard deviation) | mean of the single runs' own error | realizations | T at the centre [T⁰] |")
        w("|---|---|---|---|---|---|---|---|")
        means = {}
        for width, label, half, r in fourier_rows(fourier):
            if r is None:
                w(f"| {width:g} | {label} | {2 * half:g} | not in this output (profiles before 1.4.0 wrote no "
                  "Fourier-law fit): rerun `scripts/validate-sampling` | | | | |")
                continue
            mean, se, spread, own, K, centre = r
            means[(width, label, half)] = (mean, se)
            w(f"| {width:g} | {label} | {2 * half:g} | {mean:.4f} ± {se:.4f} | {spread:.4f} | {own:.4f} | {K} | {centre:.4f} |")
        w("")
        w("The error of a mean is the realizations' scatter over √K. A single run's own error (the scatter of")
        w("its bins about the line and about the mean of q_y, as if the bins were independent; the steady errors")
        w("of single bins are not used, as one of them can be NaN) is smaller than that scatter: the bins are")
        w("correlated. The L = 20 λ⁰ runs (`--set run.particles=400000 --set system.box.y=20 --set system.layers=160")
        w("--set system.bins=40`: the same layer width, density and walls) are bracketed only.")
        w("")
        for half in FOURIER_WINDOWS:
            a, b = means.get((10, "bracketed", half)), means.get((20, "bracketed", half))
            if a and b:
                w(f"- window {2 * half:g} λ⁰, bracketed: L = 10 λ⁰ {a[0] - 1:+.4f} ± {a[1]:.4f} from κ_CE, "
                  f"L = 20 λ⁰ {b[0] - 1:+.4f} ± {b[1]:.4f}; the difference {b[0] - a[0]:+.4f} ± {np.hypot(a[1], b[1]):.4f}.")
        w("")
        w("Sampling accounts for the difference between the rules (ν_κ δt/2 with ν_κ ≈ 0.6/τ⁰: +1.5 %); the")
        w("time step and the layer width are expected to raise κ, not lower it (O(δt²), O(Δy²)). The wider slab")
        w("tests whether what is left at L = 10 λ⁰ comes from the walls' Knudsen layers reaching a centre only")
        w("3.5–5 λ⁰ away (they bend the temperature profile, and the slope then gives too small a κ): if so,")
        w("the same windows at L = 20 λ⁰, 7.5–8.5 λ⁰ from the walls, sit closer to κ_CE.")
        w("")
    print("\n".join(out))


if __name__ == "__main__":
    main()
