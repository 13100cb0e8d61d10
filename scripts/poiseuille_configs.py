#!/usr/bin/python3
"""Write the granular Poiseuille pipelines of paper 004 (configs/poiseuille*.yaml) from one rule.

Protocol (ii) of 004 Sec. III.C: the channel width is fixed at W = 1860 sigma and Kn = lambda/W
(Eq. 18) is set through the mean density, lambda = Kn W; the acceleration a = a_hat 2 T_w / (m W)
(Eq. 17) is then the same for every Kn (in reduced units sigma, m, T_w = T0 = 1).

Resolution rule (documented in docs/user-guide.md; the paper used delta y = lambda/3 ... lambda/200,
Sec. III.D.1):
  layers  M   = max(40, ceil(9 / Kn))        delta y = min(lambda/9, W/40): the paper's lambda/9 for
                                             inelastic gases at small Kn, lambda/200 at Kn = 5
  time step dt = min(0.02 tau0, 0.5 delta y / u_R)   a particle crosses at most half a layer per step
                                             at the thermal speed, and collides with probability
                                             <= 2 % per step. Diagnostics sample on both sides of the
                                             collisions (bracketed sampling), so stresses and Delta T
                                             carry no O(dt) bias of sampling after them (when they did,
                                             dt = 0.05 tau0 at Kn = 0.1 put N1(0) 20 % high)
  sampling     every 4 steps (bracketed: two samples each time). 100 realizations of the Kn = 0.5,
                                             e_n = 0.9 channel (2e4 particles, 88 tau0) scatter the same
                                             to 3 digits (Q 0.00413, T(0) 0.00234, rho(0) 0.0026) as at
                                             every 2 steps, with 39 % less time in the diagnostics:
                                             consecutive samples are correlated over many steps
  relaxation t_r = max(0.18 / Kn^2, 2 / Kn, 1) tau0 (diffuse walls): the e-folding time of the slowest viscous mode,
                                             W^2 / (pi^2 eta / rho) = tau0 / (5.55 Kn^2) for hard
                                             spheres, or two wall-to-wall flights W / u_R = tau0 / Kn,
                                             and at least one mean free time (at large Kn the particles
                                             flying nearly parallel to the walls relax by collisions)
                                             The sweeps whose figures need only Q (a_hat = 10, the
                                             walls, the linear-response check) cap dt at 0.05 tau0.
  walls        Maxwell walls of accommodation acc < 1 exchange momentum slowly: the wall time
                                             (2 - acc)/acc x 2/Kn tau0 replaces 2/Kn in t_r
  steady test  E(t) window means over 2 t_r agree within 0.2 % or within two standard errors of
                                             their difference (noise), not before 4 t_r (Appendix); near
                                             linear response (the a_hat = min(0.05, 0.2 Kn) sweep) E
                                             hardly feels the flow, so not before 8 t_r
  stop         22 t_r: the test passes near 10 t_r, leaving about 12 t_r (32-64 jackknife batches,
                                             corrected for their autocorrelation) of averaging, about 7
                                             integrated autocorrelation times of Q at Kn = 0.5, where
                                             the errors hold (docs/validation/README.md)
Run:  scripts/poiseuille_configs.py   (rewrites the configs; the committed files are its output)
"""
import math
import os

W_SIGMA = 1860.0  # 004 Sec. III.C
KNUDSEN = [0.02, 0.03, 0.05, 0.1, 0.2, 0.5, 1, 2, 5, 10]
HEADER = "# Written by scripts/poiseuille_configs.py (the resolution rule is documented there and in docs/user-guide.md).\n"


def rule(kn, dt_cap=0.02, min_factor=4, accommodation=1.0, stop_factor=22):
    layers = max(40, math.ceil(9.0 / kn))
    dy_over_lambda = 1.0 / (layers * kn)
    dt = min(dt_cap, 0.5 * dy_over_lambda)  # tau0 = lambda / u_R, so delta y / u_R = (delta y / lambda) tau0
    t_r = max(0.18 / kn**2, 2.0 / kn * (2.0 - accommodation) / accommodation, 1.0)
    return dict(layers=layers, dt=float(f"{dt:.4g}"), window=float(f"{2 * t_r:.4g}"),
                min_time=float(f"{min_factor * t_r:.4g}"), stop=float(f"{stop_factor * t_r:.4g}"), t_r=t_r)


def acceleration(a_hat, t_wall=1.0):
    return a_hat * 2.0 * t_wall / W_SIGMA  # Eq. 17 in reduced units (m = 1, sigma = 1)


def kn_variant(kn, dt_cap, a_hat_of_kn=None, accommodation=1.0, stop_factor=22):
    # near linear response E(t) hardly feels the flow: wait 8 t_r (the slowest mode down to 3e-4)
    r = rule(kn, dt_cap, 8 if a_hat_of_kn else 4, accommodation, stop_factor)
    extra = f"forcings.0.acceleration.value: {acceleration(a_hat_of_kn(kn)):.8g}, " if a_hat_of_kn else ""
    return (f'    "{kn:g}": {{system.mean_free_path: {kn * W_SIGMA:.6g}, system.layers: {r["layers"]}, {extra}'
            f'run.time_step.value: {r["dt"]:g}, run.stop.time: {r["stop"]:g}, '
            f'diagnostics.0.steady_window: {r["window"]:g}, diagnostics.0.min_time: {r["min_time"]:g}}}\n')


def pipeline(name, comment, kn, alpha, a_hat, walls, particles, sweep=None, seed=4, dt_cap=0.02, stop_factor=22,
             follow_temperature=False, accommodation=0.5, steady_sigmas=None, wall_fit_reach=None):
    r = rule(kn, dt_cap, stop_factor=stop_factor)
    walls_text = {
        "diffuse": "  y_min: {plugin: diffuse_wall, temperature: 1.0}\n  y_max: {plugin: diffuse_wall, temperature: 1.0}\n",
        "maxwell": f"  y_min: {{plugin: maxwell_wall, temperature: 1.0, accommodation: {accommodation:g}}}\n"
                   f"  y_max: {{plugin: maxwell_wall, temperature: 1.0, accommodation: {accommodation:g}}}\n",
    }[walls]
    text = HEADER + comment + f"""run:
  seed: {seed}
  particles: {particles}
  time_step: {{value: {r["dt"]:g}, unit: tau0{", follow_temperature: true" if follow_temperature else ""}}}
  stop: {{time: {r["stop"]:g}}}
  sample_every: 4
  record_every: 100
system:
  mean_free_path: {kn * W_SIGMA:.6g}      # lambda0 in sigma: Kn = lambda0 / W = {kn:g} (004 Eq. 18)
  temperature: 1.0                 # T0 = T_w: outputs in T_w and u_R = sqrt(2 T_w/m) (004 Eq. 19)
  domain: slab
  box: {{y: {{value: {W_SIGMA:g}, unit: sigma}}}}   # W / d = 1860 (004 Sec. III.C)
  layers: {r["layers"]}                       # max(40, ceil(9/Kn)): delta y = min(lambda/9, W/40)
initial_state: maxwellian
collision: {{plugin: inelastic_hard_spheres, alpha: {alpha:g}}}
forcings:
  - {{plugin: body_acceleration, acceleration: {{value: {acceleration(a_hat):.8g}, unit: reduced}}}}   # a_hat = {a_hat:g} (Eq. 17)
boundaries:
{walls_text}diagnostics:
  - {{plugin: poiseuille_channel, steady_window: {r["window"]:g}, min_time: {r["min_time"]:g}, steady_tolerance: 0.002{f", steady_sigmas: {steady_sigmas:g}" if steady_sigmas else ""}{f", wall_fit_reach: {wall_fit_reach:g}" if wall_fit_reach else ""}}}
  - energy_balance
"""
    if sweep:
        text += "sweep:\n" + sweep
    text += f"output: {{file: {name}.h5}}\n"
    return text


def kn_axis(kns=KNUDSEN, dt_cap=0.02, a_hat_of_kn=None, stop_factor=22):
    return "  Kn:\n" + "".join(kn_variant(k, dt_cap, a_hat_of_kn, stop_factor=stop_factor) for k in kns)


def walls_axis(accommodations, kns, dt_cap):
    """Accommodation x Kn as one axis: the run length depends on both (the wall time of the rule)."""
    lines = []
    for acc in accommodations:
        for kn in kns:
            variant = kn_variant(kn, dt_cap, accommodation=acc).strip()
            key, rest = variant.split(": ", 1)
            lines.append(f'    "{acc:g}, {kn:g}": {{boundaries.y_min.accommodation: {acc:g}, '
                         f'boundaries.y_max.accommodation: {acc:g}, {rest[1:]}\n')
    return "  walls_Kn:\n" + "".join(lines)


def linear_a_hat(kn):
    """a_hat small enough for linear response: the centre-line Mach number u(0)/u_R ~ a_hat delta/8
    (Navier-Stokes, delta = 0.888/Kn) stays below about 0.03, so viscous heating (~ Mach^2) stays
    below 0.1 %; at a_hat = 0.1 and Kn = 0.02 the heating lowered Q by 11 %."""
    return min(0.05, 0.2 * kn)


def a_hat_axis(values):
    return "  a_hat:\n" + "".join(
        f'    "{a:g}": {{forcings.0.acceleration.value: {acceleration(a):.8g}}}\n' for a in values)


def resolution_axis(kns, widths=(0.2, 0.1)):
    """Kn x resolution as one axis (issue 29 item 3): the rule's equal layers, then layers sized to the
    local mean free path (at most w local lambda and at most the rule's equal width W/M wide, frozen at
    the end of the rule's min_time, 4 t_r) at w = 0.2 and 0.1, w = 0.2 at half the time step, and
    w = 0.1 with twice the sampling bins (the wall gradients' fit spans wall_fit_bins bins: half as
    wide; the fit over wall_fit_reach keeps its reach). The other variants sample on the rule's equal bins, so that between them only the collision
    layers and the time step change. Without the bound W/M the widest dilute wall layers were 6-8 times
    the equal ones (0.71 and 0.86 against 0.11 lambda0 at Kn = 0.05 and 0.03, e_n = 0.7, w = 0.2) and Q moved by 10-21
    standard errors between w = 0.2 and 0.1."""
    lines = []
    for kn in kns:
        r = rule(kn)
        def frozen(w):
            return (f'{{mean_free_paths: {w:g}, after: {r["min_time"]:g}, '
                    f'max_width: {{value: {W_SIGMA / r["layers"]:.15g}, unit: sigma}}}}')
        variants = [("uniform", str(r["layers"]), r["dt"], r["layers"])] + [
            (f"w{w:g}", frozen(w), r["dt"], r["layers"]) for w in widths] + [
            (f"w{widths[0]:g} dt/2", frozen(widths[0]), r["dt"] / 2, r["layers"]),
            (f"w{widths[1]:g} bins x2", frozen(widths[1]), r["dt"], 2 * r["layers"])]
        for name, layers, dt, bins in variants:
            lines.append(f'    "{kn:g} {name}": {{system.mean_free_path: {kn * W_SIGMA:.6g}, system.layers: {layers}, '
                         f'system.bins: {bins}, run.time_step.value: {dt:g}, run.stop.time: {r["stop"]:g}, '
                         f'diagnostics.0.steady_window: {r["window"]:g}, diagnostics.0.min_time: {r["min_time"]:g}}}\n')
    return "  Kn_resolution:\n" + "".join(lines)


def main():
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "configs")
    files = {
        "poiseuille": pipeline(
            "poiseuille", "# Granular Poiseuille flow (paper 004), protocol (ii): W/d = 1860, Kn = 0.05, e_n = 0.9, a_hat = 0.5,\n"
            "# fully diffuse walls at T_w. The representative near-continuum case of Figs. 3-16.\n",
            0.05, 0.9, 0.5, "diffuse", 100000),
        "poiseuille_fig2": pipeline(
            "poiseuille_fig2", "# The code-validation case of 004 Fig. 2 (and Fig. 13): a molecular gas (e_n = 1) at Kn = 0.1,\n"
            "# a_hat = 0.3, against Mansour et al. (ref. 13) and Uribe & Garcia (ref. 14).\n",
            0.1, 1.0, 0.3, "diffuse", 100000),
        "poiseuille_sweep": pipeline(
            "poiseuille_sweep", "# Kn x e_n at a_hat = 0.5, fully diffuse walls (004 Figs. 3-21).\n",
            0.05, 0.9, 0.5, "diffuse", 50000,
            sweep="  collision.alpha: [0.7, 0.9, 0.99, 1.0]\n" + kn_axis()),
        "poiseuille_bimodality_sweep": pipeline(
            "poiseuille_bimodality_sweep", "# The nearly elastic gases of Figs. 7-9 and 17-18 (e_n = 0.95 for Fig. 17) at a_hat = 0.5.\n",
            0.05, 0.99, 0.5, "diffuse", 50000,
            sweep="  collision.alpha: [0.95, 0.995, 0.999]\n" + kn_axis()),
        "poiseuille_fig9b_sweep": pipeline(
            "poiseuille_fig9b_sweep", "# Fig. 9(b): the rarefaction-driven unimodal-to-bimodal transition of T(y)/T(0) at e_n = 0.9999,\n"
            "# a_hat = 0.5, with increasing Kn.\n",
            0.05, 0.9999, 0.5, "diffuse", 50000,
            sweep=kn_axis([0.02, 0.03, 0.05, 0.1, 0.2])),
        "poiseuille_fig22": pipeline(
            "poiseuille_fig22", "# Fig. 22(b, c): the steady profiles of the elastic gas at Kn = 0.05, a_hat = 0.5 averaged over four\n"
            "# consecutive windows of 4 t_r = 288 tau0 (t_r = 72 tau0) from 8 t_r; the sweep's steady test passed at 6 t_r.\n"
            "# All cases of a sweep share the seed, so the four are windows of one trajectory. The windows are placed by\n"
            "# hand: min_time on a boundary of the steady test's 144 tau0 windows and any change accepted\n"
            "# (steady_tolerance 1), so that averaging starts exactly at min_time.\n",
            0.05, 1.0, 0.5, "diffuse", 50000,
            sweep="  window:\n" + "".join(
                f'    "{k + 1}": {{diagnostics.0.min_time: {576 + 288 * k}, run.stop.time: {864 + 288 * k}, '
                f'diagnostics.0.steady_tolerance: 1}}\n' for k in range(4))),
        "poiseuille_restitution_sweep": pipeline(
            "poiseuille_restitution_sweep", "# Against e_n at Kn = 0.05, 1 and 5 (Figs. 4c-d, 7b, 10d, 12b): the e_n the other sweeps lack.\n",
            0.05, 0.9, 0.5, "diffuse", 50000,
            sweep="  collision.alpha: [0.5, 0.6, 0.8]\n" + kn_axis([0.05, 1, 5])),
        "poiseuille_a5_sweep": pipeline(
            "poiseuille_a5_sweep", "# The triangles of Fig. 8: the bimodality phase boundary at a_hat = 5, Kn 0.1-1 (where the\n"
            "# a_hat = 0.5 boundaries of e_n >= 0.99 lie; below Kn = 0.1 one case takes over half an hour). The gas heats\n"
            "# to several T_w, so the time step follows the temperature (dt = rule x sqrt(T0/T)).\n",
            0.05, 0.99, 5, "diffuse", 50000, follow_temperature=True,
            sweep="  collision.alpha: [0.99, 0.995, 0.999, 1.0]\n" + kn_axis([0.1, 0.2, 0.5, 1])),
        "poiseuille_a10_sweep": pipeline(
            "poiseuille_a10_sweep", "# The flow rate at a_hat = 10 (Fig. 20b): Kn 0.1-10 x e_n. The gas heats to tens of T_w, so the\n"
            "# time step follows the temperature (dt = rule x sqrt(T0/T)).\n",
            0.1, 0.9, 10, "diffuse", 50000, dt_cap=0.05, follow_temperature=True,
            sweep="  collision.alpha: [0.9, 0.99, 1.0]\n" + kn_axis([0.1, 0.2, 0.5, 1, 2, 5, 10], dt_cap=0.05)),
        "poiseuille_linear_sweep": pipeline(
            "poiseuille_linear_sweep", "# The elastic gas near linear response, a_hat = min(0.05, 0.2 Kn): Q(Kn) against the linearised\n"
            "# BGK solution of scripts/poiseuille_reference.py (docs/poiseuille-reference.md). Stopped at 44 t_r:\n"
            "# E(t) hardly feels so weak a flow, so the steady test may pass late (at 22 t_r the Kn = 0.2 case\n"
            "# passed at its stop and had no averaging window).\n",
            0.05, 1.0, 0.01, "diffuse", 50000, dt_cap=0.05, stop_factor=44,
            sweep=kn_axis(dt_cap=0.05, a_hat_of_kn=linear_a_hat, stop_factor=44)),
        "poiseuille_walls_sweep": pipeline(
            "poiseuille_walls_sweep", "# The Knudsen minimum with partially diffuse walls (004 Sec. VI): Maxwell walls of accommodation\n"
            "# 0.5 and 0.1 x Kn, e_n = 0.9 and 0.99 (accommodation 1 is poiseuille_sweep.yaml). One axis holds\n"
            "# accommodation and Kn together because the run length depends on both: the wall time\n"
            "# (2 - acc)/acc 2/Kn tau0 of the resolution rule.\n",
            0.05, 0.9, 0.5, "maxwell", 50000, dt_cap=0.05,
            sweep="  collision.alpha: [0.9, 0.99]\n" + walls_axis([0.5, 0.1], [0.05, 0.1, 0.2, 0.5, 1, 2, 5, 10], 0.05)),
        "poiseuille_resolution_sweep": pipeline(
            "poiseuille_resolution_sweep", "# The small-Kn points of Figs. 4, 7 and 13-16 resolved (issue 29 item 3): at each Kn, the rule's equal\n"
            "# layers against layers sized to the local mean free path (w = 0.2 and 0.1 local lambda and at most the\n"
            "# equal layers' width, frozen at 4 t_r), w = 0.2 at half the time step and w = 0.1 with twice the sampling\n"
            "# bins. e_n is set per run (scripts/validate-poiseuille-resolution). The steady test allows 3 standard\n"
            "# errors (the main sweep's 2 never passed one case whose window means scatter by 0.3 % with no trend).\n"
            "# The wall values are also fitted over one lambda0 from each wall (wall_fit_reach: 9 bins, 18 with twice the\n"
            "# bins), so that the slip can be compared across the sampling bins.\n",
            0.05, 0.7, 0.5, "diffuse", 50000, steady_sigmas=3, wall_fit_reach=1,
            sweep=resolution_axis([0.02, 0.03, 0.05])),
        "poiseuille_knudsen_minimum_sweep": pipeline(
            "poiseuille_knudsen_minimum_sweep", "# The Knudsen minimum of Q (Fig. 20a, a_hat = 0.5, diffuse walls) on grids twice and four times as fine\n"
            "# as the main sweep's around it (0.7, 1.4, 3; then 0.85, 1.2, 1.7, 2.4 between), so that the report can show\n"
            "# whether the grid still moves it (issue 29 item 3); realizations are set per run\n"
            "# (scripts/validate-poiseuille-resolution).\n",
            1.0, 0.9, 0.5, "diffuse", 50000,
            sweep="  collision.alpha: [0.7, 0.9, 0.99, 1.0]\n" + kn_axis([0.5, 0.7, 0.85, 1, 1.2, 1.4, 1.7, 2, 2.4, 3, 5, 10])),
        "poiseuille_specular": pipeline(
            "poiseuille_specular", "# Specular walls (accommodation 0) have no steady state: collisions and specular reflections\n"
            "# conserve x momentum, so the mean streamwise velocity grows as a t and Q (Eq. 40) as Kn t/tau0.\n"
            "# The validation checks that slope (stop at 10 t_r: E grows as t^2).\n",
            1.0, 0.9, 0.5, "maxwell", 50000, dt_cap=0.05, stop_factor=10, accommodation=0.0,
            sweep=kn_axis([0.1, 1, 10], dt_cap=0.05, stop_factor=10)),
    }
    for name, text in files.items():
        with open(os.path.join(root, name + ".yaml"), "w") as f:
            f.write(text)
        print("wrote configs/" + name + ".yaml")
    print("Kn      layers  dt[tau0]  t_r[tau0]  stop[tau0]  steps")
    for kn in KNUDSEN:
        r = rule(kn)
        print(f"{kn:<7g} {r['layers']:<7d} {r['dt']:<9g} {r['t_r']:<10.4g} {r['stop']:<11g} {r['stop'] / r['dt']:.3g}")


if __name__ == "__main__":
    main()
