#!/usr/bin/python3
"""docs/validation/heat-flux-anchor.md from the long runs of configs/heat_flux_anchor.yaml and the time-step
scan of configs/heat_flux_anchor_dt.yaml (run by scripts/validate-heat-flux): the elastic anchor of paper 001,
kappa'/kappa0 = 1.025218 at alpha = 1, from long runs at eps* = 0.0125-0.075 extrapolated to eps* -> 0.

Usage: heat_flux_anchor_report.py OUTDIR > docs/validation/heat-flux-anchor.md
The runs are found in OUTDIR by their provenance (scripts/report_runs.py), whatever their file names;
anchor_long.seconds in OUTDIR, if there, is the long runs' wall time.
"""
import os
import sys

import h5py
import numpy as np

from heat_flux_report import anchor_extrapolation, short_anchor, weighted_fit
import report_figures
import report_runs
from report_figures import runs_line

AFTER = 10.0               # tau: the averaging window starts here (run.average_after)
BATCHES = 20


def batch_mean(x, batches=BATCHES):
    """Mean and standard error from `batches` consecutive batch means."""
    b = np.array([p.mean() for p in np.array_split(x, batches)])
    return x.mean(), b.std(ddof=1) / np.sqrt(batches)


def fit(eps, k, e, powers):
    """k = sum c_j eps^(2 j), j in powers, by weighted least squares: (coefficients, covariance, chi2)."""
    return weighted_fit(np.vstack([eps ** (2 * j) for j in powers]).T, k, e)


def elastic_reference_in(path):
    """The converged Sonine kappa/kappa0 at alpha = 1 (001, ref. 37) that heat_flux wrote into the output at path."""
    with h5py.File(path, "r") as f:
        return float(f["cases/0/diagnostics/heat_flux/elastic_reference_kappa_over_kappa0"][()])


def long_runs(path):
    """configs/heat_flux_anchor.yaml's output: (table rows, eps*, kappa'/kappa0 and its error per eps* (the
    realizations combined by their weights), the run's time step in tau)."""
    elastic = elastic_reference_in(path)
    f = h5py.File(path, "r")
    run0 = f["cases/0/run"].attrs
    anchor_dt = round(float(run0["final_time_tau0"]) / float(run0["steps"]), 6)  # tau (tau0 = tau: T stays T0)
    rows, eps, kv, ke = [], [], [], []
    for key in sorted(f["cases"].keys(), key=int):
        hf = f["cases"][key]["diagnostics/heat_flux"]
        e_star = float(hf["epsilon_star"][()])
        per = []
        for r in sorted(hf["realizations"].keys(), key=int):
            g = hf["realizations"][r]
            t = np.array(g["time"][:])
            x = np.array(g["conductivity_over_kappa0"][:])[t >= AFTER]
            per.append(batch_mean(x) + (t[-1],))
        m = np.array([p[0] for p in per])
        s = np.array([p[1] for p in per])
        wgt = 1 / s ** 2
        mean, err = float((m * wgt).sum() / wgt.sum()), float(1 / np.sqrt(wgt.sum()))
        eps.append(e_star)
        kv.append(mean)
        ke.append(err)
        rows.append([f"{e_star:g}", f"{per[0][2]:.0f}"] + [f"{p[0]:.4f} ± {p[1]:.4f}" for p in per] +
                    [f"{mean:.4f} ± {err:.4f}", f"{(mean - elastic) / err:+.1f}"])
    return rows, np.array(eps), np.array(kv), np.array(ke), anchor_dt


def time_step_runs(dt_path):
    """configs/heat_flux_anchor_dt.yaml's output: dt, kappa'/kappa0 and its error per dt, and the straight line
    in dt (coefficients, covariance, chi2)."""
    fd = h5py.File(dt_path, "r")
    dts, dk, de = [], [], []
    for key in sorted(fd["cases"].keys(), key=int):
        g = fd["cases"][key]
        hf = g["diagnostics/heat_flux"]
        t = np.array(hf["time"][:])
        m, e = batch_mean(np.array(hf["conductivity_over_kappa0"][:])[t >= AFTER])
        dts.append(float(g.attrs["sweep.dt"]))
        dk.append(m)
        de.append(e)
    dts, dk, de = np.array(dts), np.array(dk), np.array(de)
    c, cov, chi = weighted_fit(np.vstack([np.ones_like(dts), dts]).T, dk, de)
    return dts, dk, de, c, cov, chi


def both_limits(k0, k0e, slope, slope_e, anchor_dt):
    """kappa'(0) of the eps* fit at the long runs' dt, moved to dt -> 0 by the dt scan's slope: (value, error)."""
    return k0 - slope * anchor_dt, float(np.hypot(k0e, slope_e * anchor_dt))


def anchor_outputs(runs):
    """The paths of the long runs (configs/heat_flux_anchor.yaml) and of the time-step scan
    (configs/heat_flux_anchor_dt.yaml swept over dt alone) among runs (report_runs.Runs); None where absent."""
    long, scan = runs.one(config="heat_flux_anchor"), runs.one(config="heat_flux_anchor_dt", axes=("dt",))
    return (long.path if long else None), (scan.path if scan else None)


def anchor(runs):
    """What heat-flux.md quotes of these runs, found among runs (None without them): kappa'(0)/kappa0 at eps* -> 0
    and dt -> 0 with its error, the dt slope (per tau) with its error, the eps*^2 coefficient c, and the runs."""
    path, dt_path = anchor_outputs(runs)
    if not (path and dt_path):
        return None
    _, eps, kv, ke, anchor_dt = long_runs(path)
    c2, cov2, _ = fit(eps, kv, ke, (0, 1))
    _, _, _, c, cov, _ = time_step_runs(dt_path)
    slope, slope_e = float(c[1]), float(np.sqrt(cov[1, 1]))
    value, error = both_limits(float(c2[0]), float(np.sqrt(cov2[0, 0])), slope, slope_e, anchor_dt)
    return {"value": value, "error": error, "slope": slope, "slope_error": slope_e, "c": float(c2[1]),
            "runs": runs_line(path, dt_path)}


def main():
    d = sys.argv[1]
    found = report_runs.index(d)
    path, dt_path = anchor_outputs(found)
    if not path:
        raise SystemExit(f"heat_flux_anchor_report: no output of configs/heat_flux_anchor.yaml in {d}: run `scripts/validate-heat-flux`")
    elastic = elastic_reference_in(path)
    out = []
    w = out.append
    w("# Validation: the elastic anchor of paper 001 by long runs")
    w("")
    runs = [r for r in (path, dt_path) if r]
    w("Every path named in this document is in the source tree. Generated by `scripts/validate-heat-flux` (`scripts/heat_flux_anchor_report.py`); do not edit by hand"
      + ("; " + runs_line(*runs) if runs else "") + ".")
    w("")
    w("At α = 1 the modified thermal conductivity κ′ equals κ, and its converged Sonine value is")
    w(f"κ/κ₀ = {elastic} (001 Sec. IV). κ′ is defined in the limit of a vanishing force (Eq. 3.9), and q_x is")
    w("odd in ε*, so κ′(ε*) = κ′(0) + c ε*² + O(ε*⁴). `configs/heat_flux_anchor.yaml`: N = 2·10⁴, δt = 0.01τ,")
    w("two realizations per ε* of 40 000, 20 000, 10 000 and 5 000 τ at ε* = 0.0125, 0.025, 0.05 and 0.075")
    w("(the run length falls as 1/ε*² so that each ε* gets about the same error), averaged from t = 10τ. Each")
    w(f"realization's error is from {BATCHES} batch means of its κ′(t) series (batches of 250–2000 τ, far longer than")
    w("the correlation time of q_x, about one mean free time); the two realizations are combined by their weights.")
    w("")
    sec = os.path.join(d, "anchor_long.seconds")
    rows, eps, kv, ke, anchor_dt = long_runs(path)
    f = h5py.File(path, "r")
    nr = len(rows[0]) - 4
    w("| ε* | run length [τ] | " + " | ".join(f"realization {r}" for r in range(nr)) + " | combined | (κ′ − 1.025218)/σ |")
    w("|" + "---|" * (nr + 4))
    for r in rows:
        w("| " + " | ".join(r) + " |")
    w("")
    c2, cov2, chi2 = fit(eps, kv, ke, (0, 1))
    k0, k0e = c2[0], float(np.sqrt(cov2[0, 0]))
    w(f"**Linear response (fit κ′(0) + c ε*², all four ε*):** κ′(0)/κ₀ = {k0:.4f} ± {k0e:.4f}, "
      f"{(k0 - elastic) / k0e:+.1f} standard errors from {elastic}; c = {c2[1]:.2f} ± {np.sqrt(cov2[1, 1]):.2f}; "
      f"χ² = {chi2:.2f} for {len(eps) - 2} degrees of freedom.")
    w("")
    if len(eps) >= 4:
        c4, cov4, chi4 = fit(eps, kv, ke, (0, 1, 2))
        w(f"With an ε*⁴ term as well: κ′(0)/κ₀ = {c4[0]:.4f} ± {np.sqrt(cov4[0, 0]):.4f} "
          f"({(c4[0] - elastic) / np.sqrt(cov4[0, 0]):+.1f} errors), χ² = {chi4:.2f} for {len(eps) - 3} degree(s) of freedom. "
          "From ε* ≤ 0.025 alone, each corrected by the fitted c ε*²: "
          f"κ′(0)/κ₀ = {np.average(kv[eps <= 0.025] - c2[1] * eps[eps <= 0.025] ** 2, weights=1 / ke[eps <= 0.025] ** 2):.4f}.")
        w("")
    at = kv[np.isclose(eps, 0.025)]
    if len(at):
        e25 = ke[np.isclose(eps, 0.025)][0]
        w(f"At the paper's ε* = 0.025 itself κ′/κ₀ = {at[0]:.4f} ± {e25:.4f}: the nonlinear response "
          f"c ε*² = {c2[1] * 0.025 ** 2:.4f} is {c2[1] * 0.025 ** 2 / e25:.1f} times that error, which is why the anchor "
          "is read in the limit ε* → 0.")
        w("")
    short = short_anchor(found)
    if short:
        _, ks, _, _, _, cs, covs, _ = anchor_extrapolation(short)
        s0, s0e = cs[0], float(np.sqrt(covs[0, 0]))
        w(f"The anchor of docs/validation/heat-flux.md ({ks} realizations per ε* of 25τ at N = 2·10⁵, δt = 0.03τ, averaged")
        w(f"over 15τ each; {runs_line(short)}): κ′(0)/κ₀ = {s0:.4f} ± {s0e:.4f}. The two extrapolations differ by")
        w(f"{s0 - k0:+.4f} ± {np.hypot(s0e, k0e):.4f} ({(s0 - k0) / np.hypot(s0e, k0e):+.1f} combined errors).")
    else:
        w("The anchor of docs/validation/heat-flux.md (heat_flux_anchor.h5) is not in this directory: run "
          "`scripts/validate-heat-flux` for the comparison.")
    w("")
    w("## The time step")
    w("")
    sampling = report_figures.h5_text(f["cases/0/diagnostics/heat_flux"].attrs.get("sampling", ""))
    if sampling.startswith("bracketed"):
        w("The heat flux is sampled on both sides of the collision stage (bracketed sampling, `run.sampling`'s default")
        w("since SDK 6.1), so the sample is no longer taken at one end of the sawtooth that the force and the collisions")
        w("draw each step. `configs/heat_flux_anchor_dt.yaml` measures what is left of the time step's effect at ε* = 0.05:")
    else:
        w("The heat flux is sampled once per step, after the force (Eq. 4.1) and the thermostat (Eq. 4.2); the")
        w("collisions of the next step relax it. The sample sits at the top of a sawtooth, an O(δt) bias of about")
        w("½ ν_q δt (ν_q the relaxation rate of q, of order the collision frequency). `configs/heat_flux_anchor_dt.yaml`")
        w("measures it at ε* = 0.05:")
    w("")
    if not dt_path:
        w("*(the time-step scan, configs/heat_flux_anchor_dt.yaml, is not in this directory: run `scripts/validate-heat-flux`)*")
    else:
        dts, dk, de, c, cov, chi = time_step_runs(dt_path)
        w("| δt [τ] | κ′/κ₀ at ε* = 0.05 |")
        w("|---|---|")
        for a, b, e in zip(dts, dk, de):
            w(f"| {a:g} | {b:.4f} ± {e:.4f} |")
        w("")
        slope, slope_e = c[1], np.sqrt(cov[1, 1])
        w(f"Straight line in δt: κ′/κ₀ = {c[0]:.4f} ± {np.sqrt(cov[0, 0]):.4f} at δt → 0, slope {slope:.3f} ± {slope_e:.3f} per τ "
          f"(χ² = {chi:.2f} for {len(dts) - 2} degrees of freedom).")
        w("")
        corrected, ce = both_limits(k0, k0e, slope, slope_e, anchor_dt)
        w(f"**Both limits.** Taking the same relative bias at every ε* (it is a property of the sampling cycle, not of the")
        w(f"field), the long runs above (δt = {anchor_dt:g}τ) give κ′(0)/κ₀ = {k0:.4f} − {slope * anchor_dt:.4f} = **{corrected:.4f} ± {ce:.4f}** "
          f"at ε* → 0 and δt → 0: {(corrected - elastic) / ce:+.1f} errors from {elastic}.")
    w("")
    if os.path.exists(sec):
        w("")
        w(f"Cost: {float(open(sec).read()):.0f} s wall time with `--threads 2` on the two cores.")
    print("\n".join(out))


if __name__ == "__main__":
    main()
