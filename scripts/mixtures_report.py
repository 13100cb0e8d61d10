"""Turn the outputs of scripts/validate-mixtures into docs/validation/mixtures.md: granular binary
mixtures (issue 33) -- equipartition in the elastic limit, the temperature ratio T0/T1 of the
homogeneous cooling state against the mass ratio, the size ratio and alpha beside Garzo & Dufty's
theory (Maxwellian and first Sonine), the partial cooling rates, the white-noise driven steady
state, the tracer limit, and species-resolved profiles of paper 004's Poiseuille channel.

Every theory number is read from the files (mixture_theory writes it; the SDK header
gdsmc/physics/mixture_theory.hpp computes it); this script only selects, differences and formats.

Usage: mixtures_report.py OUTDIR SECONDS [DOCDIR]  > DOCDIR/mixtures.md (figures to DOCDIR/mixtures/).
OUTDIR holds the outputs of the configs/mixture_*.yaml pipelines, found by their provenance
(scripts/report_runs.py) whatever their file names. Needs Debian's python3-h5py, python3-numpy and
python3-matplotlib."""
import os
import sys

import numpy as np

import report_runs

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

FIGDIR = "mixtures"


def need(found, what, **match):
    o = found.one(**match)
    if o is None:
        raise SystemExit(f"mixtures_report: no output for {what} ({match}) in the given folder: run scripts/validate-mixtures")
    return o


def value(g, name):
    return float(g[name][()])


def steady(g, name):
    return value(g, name + ".steady_mean"), value(g, name + ".steady_stderr")


def pm(v, e, digits=4):
    return f"{v:.{digits}f} ± {e:.{digits}f}"


def sigmas(v, e, ref):
    return f"{(v - ref) / e:+.1f}" if e > 0 else "—"


def cases(output):
    """(case, its HDF5 group) of every case of an output, in case order (a single run: one)."""
    out = []
    for c in output.cases:
        out.append((c, c.open()))
    return out


def hcs_table(output, axis_label, axis, species=("light", "heavy"), dt_note=""):
    rows = [f"| {axis_label} | T0/T1 measured | first Sonine | (meas − Sonine)/σ | Maxwellian | "
            f"ζ_{species[0]}/ζ | ζ_{species[1]}/ζ |", "|---|---|---|---|---|---|---|"]
    points = []
    for c, g in cases(output):
        t = g["diagnostics/mixture_theory"]
        s = g["diagnostics/species_moments"]
        v, e = steady(t, "temperature_ratio")
        son, mx = value(t, "gamma_sonine"), value(t, "gamma_maxwellian")
        z0, z0e = steady(s, f"zeta_ratio[{species[0]}]")
        z1, z1e = steady(s, f"zeta_ratio[{species[1]}]")
        x = c.sweep.get(axis, "")
        rows.append(f"| {x} | {pm(v, e)} | {son:.4f} | {sigmas(v, e, son)} | {mx:.4f} | {pm(z0, z0e)} | {pm(z1, z1e)} |")
        points.append((float(x), v, e, son, mx, z0, z0e))
        g.file.close()
    return "\n".join(rows), points


def driven_table(output):
    rows = ["| m1/m0 | T0/T1 measured | first Sonine | (meas − Sonine)/σ | Maxwellian | T0/T measured | T1/T measured |",
            "|---|---|---|---|---|---|---|"]
    points = []
    for c, g in cases(output):
        t = g["diagnostics/mixture_theory"]
        v, e = steady(t, "temperature_ratio")
        son, mx = value(t, "gamma_sonine"), value(t, "gamma_maxwellian")
        a, ae = steady(t, "T0_over_T")
        b, be = steady(t, "T1_over_T")
        x = c.sweep["system.species[1].mass"]
        rows.append(f"| {x} | {pm(v, e)} | {son:.4f} | {sigmas(v, e, son)} | {mx:.4f} | {pm(a, ae)} | {pm(b, be)} |")
        points.append((float(x), v, e, son, mx))
        g.file.close()
    return "\n".join(rows), points


def tracer_table(output):
    rows = ["| x0 | T0/T1 measured | first Sonine at x0 | (meas − Sonine)/σ | Maxwellian at x0 | first Sonine, x0 → 0 | "
            "Maxwellian, x0 → 0 |", "|---|---|---|---|---|---|---|"]
    for c, g in cases(output):
        t = g["diagnostics/mixture_theory"]
        v, e = steady(t, "temperature_ratio")
        son, mx = value(t, "gamma_sonine"), value(t, "gamma_maxwellian")
        x0 = g["system"].attrs["species.tracer.fraction"]
        rows.append(f"| {x0:g} | {pm(v, e)} | {son:.4f} | {sigmas(v, e, son)} | {mx:.4f} | "
                    f"{value(t, 'gamma_tracer_sonine'):.4f} | {value(t, 'gamma_tracer_maxwellian'):.4f} |")
        g.file.close()
    return "\n".join(rows)


def equipartition_table(output):
    rows = ["| m_heavy/m_light | T_light/T | T_heavy/T | (T_light/T − 1)/σ |", "|---|---|---|---|"]
    for c, g in cases(output):
        s = g["diagnostics/species_moments"]
        a, ae = steady(s, "T_ratio[light]")
        b, be = steady(s, "T_ratio[heavy]")
        rows.append(f"| {c.sweep['system.species[1].mass']} | {pm(a, ae)} | {pm(b, be)} | {sigmas(a, ae, 1.0)} |")
        g.file.close()
    return "\n".join(rows)


def poiseuille(output, docdir):
    c, g = cases(output)[0]
    s = g["diagnostics/species_moments"]
    y = s["bin_centre"][()]
    prof = {k: (s[k + ".steady_mean"][()], s[k + ".steady_stderr"][()]) for k in
            ("n_profile[light]", "n_profile[heavy]", "n_profile", "u_x_profile[light]", "u_x_profile[heavy]",
             "T_profile[light]", "T_profile[heavy]", "T_ratio_profile[heavy]")}
    x_heavy = prof["n_profile[heavy]"][0] / prof["n_profile"][0]
    # The heavy fraction's error from the two species' independent profile errors (delta method).
    nl, nle = prof["n_profile[light]"]
    nh, nhe = prof["n_profile[heavy]"]
    xe = np.sqrt((nl * nhe) ** 2 + (nh * nle) ** 2) / (nl + nh) ** 2
    bins = len(y)
    centre = slice(bins // 2 - 1, bins // 2 + 1)
    walls = [0, bins - 1]
    rows = ["| where | y/λ⁰ | heavy fraction n_h/n | T_heavy/T_light | u_x heavy / u_x light |", "|---|---|---|---|---|"]
    for name, idx in (("wall y_min", [walls[0]]), ("centre", list(range(bins))[centre]), ("wall y_max", [walls[1]])):
        xh = np.mean(x_heavy[idx])
        xhe = np.sqrt(np.sum(xe[idx] ** 2)) / len(idx)
        tr = np.mean(prof["T_profile[heavy]"][0][idx] / prof["T_profile[light]"][0][idx])
        ur = np.mean(prof["u_x_profile[heavy]"][0][idx] / prof["u_x_profile[light]"][0][idx])
        rows.append(f"| {name} | {np.mean(y[idx]):+.2f} | {pm(xh, xhe, 4)} | {tr:.4f} | {ur:.4f} |")
    os.makedirs(os.path.join(docdir, FIGDIR), exist_ok=True)
    fig, ax = plt.subplots(1, 3, figsize=(12, 3.6))
    ax[0].errorbar(y, x_heavy, yerr=xe, fmt="o-", ms=3)
    ax[0].axhline(0.5, color="grey", lw=0.8)
    ax[0].set(xlabel="y / λ⁰", ylabel="n_heavy / n", title="heavy fraction")
    for k, lab in (("u_x_profile[light]", "light"), ("u_x_profile[heavy]", "heavy")):
        ax[1].errorbar(y, prof[k][0], yerr=prof[k][1], fmt="o-", ms=3, label=lab)
    ax[1].set(xlabel="y / λ⁰", ylabel="u_x [√(2T0/m)]", title="flow velocity")
    ax[1].legend()
    for k, lab in (("T_profile[light]", "light"), ("T_profile[heavy]", "heavy")):
        ax[2].errorbar(y, prof[k][0], yerr=prof[k][1], fmt="o-", ms=3, label=lab)
    ax[2].set(xlabel="y / λ⁰", ylabel="T_i [T0]", title="species temperatures")
    ax[2].legend()
    fig.tight_layout()
    fig.savefig(os.path.join(docdir, FIGDIR, "poiseuille_profiles.png"), dpi=110)
    plt.close(fig)
    run = g.file["run"].attrs if "run" in g.file else {}
    acceptance = run["collisions"] / run["candidates"] if "candidates" in run else float("nan")
    centre_x = float(np.mean(x_heavy[centre]))
    wall_x = float(np.mean(x_heavy[walls]))
    # Where the heavy fraction is smallest, and the mixture's temperature profile's extremes.
    t_mix = (nl * prof["T_profile[light]"][0] + nh * prof["T_profile[heavy]"][0]) / (nl + nh)
    low = int(np.argmin(x_heavy))
    lowest = (float(x_heavy[low]), float(xe[low]), float(abs(y[low])), float(abs(y[int(np.argmax(t_mix))])))
    g.file.close()
    return "\n".join(rows), centre_x, wall_x, acceptance, lowest


def ratio_figure(docdir, name, xlabel, points, title):
    os.makedirs(os.path.join(docdir, FIGDIR), exist_ok=True)
    p = np.array(points)
    fig, ax = plt.subplots(figsize=(5, 3.6))
    ax.errorbar(p[:, 0], p[:, 1], yerr=p[:, 2], fmt="o", label="DSMC (gdsmc)")
    ax.plot(p[:, 0], p[:, 3], "-", label="first Sonine")
    ax.plot(p[:, 0], p[:, 4], "--", label="Maxwellian")
    ax.set(xlabel=xlabel, ylabel="T0 / T1", title=title)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(docdir, FIGDIR, name), dpi=110)
    plt.close(fig)


def main():
    outdir, seconds = sys.argv[1], sys.argv[2]
    docdir = sys.argv[3] if len(sys.argv) > 3 else "docs/validation"
    found = report_runs.index(outdir)
    eq = need(found, "equipartition", config="mixture_equipartition")
    mass = need(found, "the HCS over the mass ratio", config="mixture_hcs_sweep", unset=("sweep", "run.time_step.value"))
    size = need(found, "the HCS over the size ratio", config="mixture_hcs_sweep", axes=["system.species[1].diameter"])
    alpha = need(found, "the HCS over alpha", config="mixture_hcs_sweep", axes=["collision.alpha"])
    small_dt = need(found, "the HCS at a quarter of the time step", config="mixture_hcs_sweep", has=("run.time_step.value",))
    driven = need(found, "the driven state", config="mixture_driven_sweep")
    tracer = need(found, "the tracer limit", config="mixture_tracer_sweep")
    channel = need(found, "the Poiseuille mixture", config="mixture_poiseuille")

    mass_rows, mass_points = hcs_table(mass, "m1/m0", "system.species[1].mass")
    size_rows, size_points = hcs_table(size, "σ1/σ0", "system.species[1].diameter")
    alpha_rows, alpha_points = hcs_table(alpha, "α", "collision.alpha")
    dt_rows, _ = hcs_table(small_dt, "m1/m0", "system.species[1].mass")
    driven_rows, driven_points = driven_table(driven)
    ratio_figure(docdir, "hcs_mass_ratio.png", "m1 / m0", mass_points, "HCS, α = 0.8, σ1 = σ0, x0 = 1/2")
    ratio_figure(docdir, "driven_mass_ratio.png", "m1 / m0", driven_points, "white noise, α = 0.8")
    pois_rows, centre_x, wall_x, acceptance, lowest = poiseuille(channel, docdir)
    # The HCS cases away from the one-species point: relative deviations from the theory.
    hcs_points = [p for p in mass_points + size_points[1:] + alpha_points if abs(p[3] - 1.0) > 1e-9]
    dev = [100 * (p[1] / p[3] - 1) for p in hcs_points]
    mxdev = [100 * (p[1] / p[4] - 1) for p in hcs_points]
    dev_min, dev_max, dev_mean = min(dev), max(dev), float(np.mean(dev))
    mx_min, mx_max = min(mxdev), max(mxdev)
    beyond = sum(abs(p[1] - p[3]) > 3 * p[2] for p in hcs_points)
    worst = max(hcs_points, key=lambda p: abs(p[5] - 1.0))
    zeta_dev = 100 * abs(worst[5] - 1.0)
    zeta_sig = abs(worst[5] - 1.0) / worst[6] if worst[6] > 0 else float("inf")
    _, dt_points = hcs_table(small_dt, "m1/m0", "system.species[1].mass")
    at = {p[0]: p for p in mass_points}
    dt_text = " and ".join(f"{100 * (p[1] / at[p[0]][1] - 1):+.2f} % ({(p[1] - at[p[0]][1]) / np.hypot(p[2], at[p[0]][2]):+.1f} "
                           f"combined σ)" for p in dt_points)
    print(f"""# Validation: granular binary mixtures

Every path named in this document is in the source tree. What this checks (issue 33): a mixture of two species of inelastic hard spheres with their own
masses, diameters and restitution (`system.species`, `inelastic_hard_spheres` with
`restitution_pairs`), run by the host's scheme of candidates per pair of species. Every theory
number below is written into the output by the `mixture_theory` diagnostic (the SDK header
`gdsmc/physics/mixture_theory.hpp`: Garzó & Dufty's partial cooling rates in the Maxwellian and the
first Sonine approximation, the latter with the cumulants c_i from the linearised fourth-moment
balances, derived in `scripts/mixture_sonine_moments.py`); the measured values are steady means
over the window after `run.average_after`, ± the standard error over the 4 realizations of each case
(the scatter of the seeds). Regenerate with `scripts/validate-mixtures` ({seconds} s of runs, each on
one of the 2 shared cores of the development machine, 2026-11-28); the pipelines are
`configs/mixture_*.yaml`.

Species 0 is listed first in `system.species` (here `light`, or `tracer`), species 1 second; T0/T1
is the ratio of their temperatures T_i = m_i ⟨V²⟩_i / 3, V the velocity about the mixture's
barycentric flow.

## 1. Elastic limit: equipartition
`configs/mixture_equipartition.yaml`: α = 1, 5·10⁴ particles half and half, light (m, σ) and heavy
(m_h, 1.5σ), started at T_light = 0.5 T⁰, T_heavy = 1.5 T⁰; steady window 10 ≤ s ≤ 30.

{equipartition_table(eq)}

## 2. Homogeneous cooling state: T0/T1 against the mass ratio
`configs/mixture_hcs_sweep.yaml`: α = 0.8 for every pair, σ1 = σ0, x0 = 1/2, 5·10⁴ particles,
δt = 0.01 τ(T), window 10 ≤ s ≤ 40. ζ_i/ζ is the partial cooling rate of species i (from the
rule's per-species energy tallies) over the mixture's: 1 in the scaled HCS.

{mass_rows}

![T0/T1 against m1/m0](mixtures/hcs_mass_ratio.png)

At a quarter of the time step (δt = 0.0025 τ(T)):

{dt_rows}

### Against the size ratio (m1/m0 = 2)
{size_rows}

### Against α (m1/m0 = 4, σ1 = σ0)
{alpha_rows}

## 3. Driven steady state (white-noise thermostat)
`configs/mixture_driven_sweep.yaml`: `white_noise_thermostat` with ξ0² = 0.1 T⁰/(m τ⁰), the same
acceleration variance for every species, α = 0.8, σ1 = σ0, x0 = 1/2; the steady state has
ζ0 T0/m0 = ζ1 T1/m1 (`mixture_theory` with `state: white_noise`). Window s ≥ 25.

{driven_rows}

![T0/T1 against m1/m0, driven](mixtures/driven_mass_ratio.png)

## 4. Tracer limit
`configs/mixture_tracer_sweep.yaml`: a tracer species (4m, 1.5σ) at number fraction x0 in a gas
(m, σ), α = 0.8 for every pair, 10⁵ particles (1000 tracers at x0 = 0.01). The theory at the run's
x0 and in the limit x0 → 0 (ζ_tracer from its collisions with the gas alone):

{tracer_table(tracer)}

## 5. Poiseuille channel of paper 004 with two species
`configs/mixture_poiseuille.yaml`: Kn = 0.1 (W = 1860σ), â = 0.5, e_n = 0.9 for every pair,
diffuse walls at T_w = T⁰, light (m, σ) and heavy (4m, σ) half and half, 6·10⁴ particles, 30
sampling bins, steady window 500 ≤ t/τ⁰ ≤ 1500. {100 * acceptance:.1f} % of the candidate pairs were
accepted (weighted pairs per pair of species in the layers).

{pois_rows}

The heavy species' number fraction is {centre_x:.4f} at the centre and {wall_x:.4f} at the walls,
and smallest, {lowest[0]:.4f} ± {lowest[1]:.4f}, at |y| = {lowest[2]:.2f} λ⁰, where the mixture's
temperature peaks (|y| = {lowest[3]:.2f} λ⁰): the heavy species concentrates {"at the centre" if centre_x > wall_x
else "at the walls"}, and more generally where the gas is cold (the centre's temperature minimum and the
walls at T_w), away from the temperature maxima of the Poiseuille profile — thermal diffusion of
the heavier species down the temperature gradient. The heavy species is the hotter one everywhere
(T_heavy/T_light 1.1–1.5), as in the homogeneous states above, most of all next to the walls.

![species profiles](mixtures/poiseuille_profiles.png)

## Findings and what is not compared
- **No published DSMC numbers beside ours.** Montanero & Garzó (Granular Matter 4, 17 (2002)) and
  Dahl et al. (PRE 66, 041301 (2002)) give DSMC and MD values of T0/T1 for the HCS; their text was
  not available to us here (the stored pages give only their openings), so the comparison is with
  the theory alone. The theory is checked in `tests/sdk/mixture_kinetic_theory_test.cpp` against the
  published one-species limits (van Noije & Ernst's a2 in both states, paper 002 Eq. 18) and a
  Monte Carlo quadrature of every pair moment.
- **The first Sonine approximation against the simulation.** Over the {len(hcs_points)} HCS cases with
  m1 ≠ m0 or σ1 ≠ σ0, the measured T0/T1 lies {dev_min:+.2f} % to {dev_max:+.2f} % from the first-Sonine
  value (mean {dev_mean:+.2f} %), {beyond} of them beyond 3 standard errors; the Maxwellian
  approximation lies {mx_min:+.2f} % to {mx_max:+.2f} % away. At a quarter of the time step the m1/m0 = 4
  and 10 values move by {dt_text} from those at δt = 0.01 τ(T): no time-step trend is resolved at
  this precision, and the systematic +0.1 to +0.3 % reads as the first Sonine approximation's own
  error (the next Sonine order and the terms non-linear in c_i that it drops). An open finding, not
  a disagreement with Garzó & Dufty: their published comparisons we could not read.
- **Partial cooling rates.** ζ_0/ζ departs from 1 by at most {zeta_dev:.2f} % over the HCS cases
  ({zeta_sig:.1f} of its standard errors there); in the mass-ratio table the deviations at
  m1/m0 ≥ 6 are small but several standard errors wide and all of one sign. species_moments
  integrates T over a record window as Δt √(T_a T_b), exact for Haff's law, so a slow drift of the
  temperature ratio after s = 10 at large mass ratios is the likelier cause; not resolved here.
- **Error bars** are the standard errors of the mean over 4 realizations (the seeds' scatter): with 4
  seeds each error is itself uncertain by about ±40 %, which the σ columns inherit.
""")


if __name__ == "__main__":
    main()
