"""The speed-accuracy chart against a peer: wall (and CPU) time against the largest structural strain on the peer
sheet (bench/peer_sheet.py: 128 x 128, 1 m, 1 kg, hanging from two corners) for Blender's cloth modifier at
several qualities and for clothsim's integrators at several steps and stiffnesses, all measured in one Blender
process on one machine.

  blender -b --factory-startup --python-exit-code 1 --python bench/peer_chart.py -- CLOTHSIM_BIN SCRATCH OUT \
      [--seconds 0.5] [--qualities 1,2,...,10] [--steps 24,48,72,96,120,240,480] \
      [--stiffnesses matched,200000,1000000,2000000] [--limited 10000/0.095,10000/0.005] [--limited-steps 24,48] \
      [--symplectic matched] [--cg-tolerances 1e-3,1e-2,3e-2] [--repeats 3] [--blender-repeats 1] \
      [--blender-air-damping X] [--threads 2] [--tension 15] [--side 128] [--match 1.25] [--rows OLD.csv]

bench/peer_chart.sh wraps it and exits 77 (skipped) where blender is not installed. Writes to OUT:
peer_chart.csv (one row per run), peer_chart_matches.csv (for each Blender quality, the fastest clothsim run
whose strain is within --match x Blender's: clothsim_* among all runs, strict_* among those solved to the first
CG tolerance), peer_chart.gnuplot and peer_chart.png (svg where gnuplot has no
png terminal). docs/accuracy.md ("Against a peer") reads the committed run.

Strain is measured the same way on both peers: the grid's structural edges against their rest lengths, from the
meshes each writes (Blender's evaluated mesh at each frame, clothsim's OBJ files), the largest over all frames.
"matched" stiffness is clothsim's reading of Blender's tension: tension * (side - 1) N/m a spring
(docs/performance.md, "Peers side by side"); it stretches far more than Blender does, so the stiffer sheets are
there to reach Blender's strain. A clothsim run that exits non-zero or reports steps that failed their check
(docs/errors.md) is marked in the CSV and drawn as a cross, never as a good point, and never matched.
Strain is not motion: the sag_m column (the vertices' mean drop at the last frame) shows how far each sheet fell,
and Blender's barely does on this sheet (docs/accuracy.md, "Against a peer").
"""
import argparse
import csv
import os
import re
import shutil
import statistics
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from peer_run import run_clothsim_status  # noqa: E402
from peer_sheet import bake_blender, grid_edges, read_obj, structural_strain, write_clothsim_scene  # noqa: E402

import numpy as np  # noqa: E402

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
ap = argparse.ArgumentParser(prog="peer_chart.py")
ap.add_argument("clothsim", help="path to the clothsim binary")
ap.add_argument("scratch", help="folder for the bakes, the clothsim scenes and their frames")
ap.add_argument("out", help="folder for the CSV files and the chart")
ap.add_argument("--side", type=int, default=128, help="vertices along each side")
ap.add_argument("--seconds", type=float, default=0.5, help="simulated time")
ap.add_argument("--fps", type=int, default=24)
ap.add_argument("--qualities", default="1,2,3,4,5,6,7,8,9,10", help="Blender's quality steps (substeps a frame)")
ap.add_argument("--tension", type=float, default=15.0, help="Blender tension/compression/shear (its default 15)")
ap.add_argument("--steps", default="24,48,72,96,120,240,480",
                help="clothsim implicit steps, as 1/N s; each N a multiple of --fps, as a step must divide a frame")
ap.add_argument("--stiffnesses", default="matched,200000,1000000,2000000",
                help="clothsim stiffnesses, N/m a spring; matched = tension * (side - 1)")
ap.add_argument("--limited", default="10000/0.095,10000/0.005",
                help="clothsim implicit runs with a Provot strain limit, STIFFNESS/MAXSTRAIN each: the 'stiff "
                     "sheet' of docs/performance.md (0.095), and one limited near Blender's quality-5 strain")
ap.add_argument("--limited-steps", default="24,48", help="steps, as 1/N s, of the --limited runs")
ap.add_argument("--symplectic", default="matched",
                help="stiffnesses to run symplectic Euler at its largest stable step (as `clothsim validate` "
                     "estimates it, rounded up to divide a frame); empty for none")
ap.add_argument("--cg-tolerances", default="1e-3,1e-2,3e-2",
                help="clothsim implicit: relative CG residuals, comma-separated; the unlimited ladder runs at each, the "
                     "limited and symplectic runs at the first. A looser solve damps the fall: see the sag_m column")
ap.add_argument("--repeats", type=int, default=3, help="clothsim runs of each point; medians are kept")
ap.add_argument("--blender-repeats", type=int, default=1, help="bakes of each quality; medians are kept")
ap.add_argument("--blender-air-damping", type=float, default=None,
                help="Blender's air_damping (its default 1: a drag per vertex, not per kg, so on this light sheet it "
                     "slows the fall; the sag_m column shows how far each sheet fell)")
ap.add_argument("--rows", default="", help="an earlier run's peer_chart.csv: redo the matches and the chart "
                                             "from its rows instead of running anything")
ap.add_argument("--threads", type=int, default=2, help="threads for both")
ap.add_argument("--match", type=float, default=1.25, help="a clothsim strain within this factor of Blender's "
                                                          "counts as matched")
args = ap.parse_args(argv)
bad = [n for n in (args.steps + "," + args.limited_steps).split(",") if n and int(n) % args.fps]
if bad:  # clothsim's scene writer would round them to another step, and the ladder would repeat a point
    ap.error(f"--steps {','.join(bad)}: not multiples of --fps {args.fps}")

side, fps = args.side, args.fps
frames = round(args.seconds * fps)
os.makedirs(args.scratch, exist_ok=True)
os.makedirs(args.out, exist_ok=True)
EDGES = grid_edges(side)
TOLERANCES = [float(t) for t in args.cg_tolerances.split(",")]
BLENDER_SETTINGS = None if args.blender_air_damping is None else {"air_damping": args.blender_air_damping}


def stiffness_of(word):
    return args.tension * (side - 1) if word == "matched" else float(word)


def load1():
    return os.getloadavg()[0]


def median_of(runs, key):
    return statistics.median(r[key] for r in runs)


def blender_row(quality):
    loads, runs = [], []
    for _ in range(args.blender_repeats):
        loads.append(load1())
        runs.append(bake_blender(side, fps, frames, quality, args.tension, args.threads, BLENDER_SETTINGS))
    r = runs[0]
    ok = all(x["finite"] for x in runs)
    return dict(peer="blender", method=f"quality {quality}", stiffness="", step_s=r["step"], quality=quality,
                steps=r["steps"], repeats=len(runs), wall_s=median_of(runs, "wall"), cpu_s=median_of(runs, "cpu"),
                max_strain=median_of(runs, "max_strain"), sag_m=r["sag"], cg_per_step="", exit="",
                status="ok" if ok else "non-finite", load1=statistics.median(loads))


def symplectic_step(stiffness):
    """The largest symplectic Euler step `clothsim validate` estimates for the sheet (springs and damping)."""
    xml = os.path.join(args.scratch, "validate.xml")
    write_clothsim_scene(xml, os.path.join(args.scratch, "validate"), side, fps, frames, "symplectic", 1.0 / fps,
                         stiffness)
    text = subprocess.run([args.clothsim, "validate", xml], capture_output=True, text=True).stdout
    return float(re.search(r"largest stable step: symplectic ([0-9.eE+-]+) s", text).group(1))


def clothsim_measure(pattern):
    """Largest structural strain over the frames written (rest lengths from frame 1, the flat start) and the mean
    drop of the vertices at the last frame written."""
    first, tris = read_obj(pattern.format(1))
    tri_edges = {tuple(sorted(e)) for t in tris for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))}
    assert all(tuple(sorted(e)) in tri_edges for e in EDGES[::97]), "grid layout is not row-major"
    rest = np.linalg.norm(first[EDGES[:, 1]] - first[EDGES[:, 0]], axis=1)
    worst, last = 0.0, first
    for f in range(2, 2 + frames):
        if not os.path.exists(pattern.format(f)):
            break  # a diverged run writes no frame from the failed one on
        last, _ = read_obj(pattern.format(f))
        worst = max(worst, structural_strain(last, EDGES, rest))
    return worst, float(np.mean(first[:, 1] - last[:, 1]))


def clothsim_row(integrator, stiffness_word, step, limit=0.0, tolerance=None):
    stiffness = stiffness_of(stiffness_word)
    tolerance = TOLERANCES[0] if tolerance is None else tolerance
    name = f"{integrator}_{stiffness:g}_{step:.6g}_tol{tolerance:g}" + (f"_limit{limit:g}" if limit else "")
    out = os.path.join(args.scratch, name)
    xml = os.path.join(args.scratch, name + ".xml")
    stats = os.path.join(args.scratch, name + "_stats.json")
    loads, runs = [], []
    for _ in range(args.repeats):
        shutil.rmtree(out, ignore_errors=True)  # no frame of an earlier run may be measured as this one's
        pattern = write_clothsim_scene(xml, out, side, fps, frames, integrator, step, stiffness, tolerance,
                                       limit, preconditioner="multigrid" if integrator == "implicit" else "")
        loads.append(load1())
        rc, wall, cpu, st, err = run_clothsim_status(args.clothsim, xml, args.threads, stats)
        strain, sag = clothsim_measure(pattern)
        runs.append(dict(rc=rc, wall=wall, cpu=cpu, st=st, err=err, strain=strain, sag=sag))
    r = runs[0]
    failed = sum(fr.get("failed_steps", 0) for fr in r["st"]["frames"])
    if r["rc"] != 0:
        found = re.search(r"strain rose from [0-9.e+-]+ to ([0-9.e+-]+)", r["err"])
        status = f"failed: exit {r['rc']}" + (f" (strain {found.group(1)} in its last step)" if found else "")
    elif failed:
        status = f"failed checks: {failed} of {r['st']['steps']} steps (exit 0)"
    else:
        status = "ok"
    if r["err"].strip():
        print(f"{name}: {r['err'].strip()}", file=sys.stderr)
    label = "symplectic Euler" if integrator == "symplectic" else (
        "implicit" + (f", maxStrain {limit:g}" if limit else "") + (f", cgTolerance {tolerance:g}" if tolerance != TOLERANCES[0] else ""))
    return dict(peer="clothsim", method=label, stiffness=f"{stiffness:g}", step_s=r["st"]["dt"], quality="",
                steps=r["st"]["steps"], repeats=len(runs), wall_s=statistics.median(x["wall"] for x in runs),
                cpu_s=statistics.median(x["cpu"] for x in runs), max_strain=statistics.median(x["strain"] for x in runs),
                sag_m=r["sag"], cg_per_step=f"{r['st'].get('cg_iterations', 0) / max(1, r['st']['steps']):.1f}",
                exit=r["rc"], status=status, load1=statistics.median(loads))


def fraction(step):
    n = 1.0 / step
    return f"1/{n:.0f}" if abs(n - round(n)) < 1e-4 * n and n < 1000 else f"{step:.2g}"  # a CSV's 6 digits


def chart_x(row):
    """A failed run is drawn at the strain it reached, or the strain its error names, or 1 (off the good runs)."""
    found = re.search(r"\(strain ([0-9.e+-]+)", row["status"])
    return max(row["max_strain"], float(found.group(1)) if found else 0.0) or 1.0


def write_chart(rows):
    dat = os.path.join(args.out, "peer_chart.dat")
    series = []  # (title, style, rows)
    series.append(("Blender cloth (labels: quality)", "lp pt 7 ps 1.3 lc rgb '#d95f02'",
                   [r for r in rows if r["peer"] == "blender" and r["status"] == "ok"]))
    colours = ["#1b9e77", "#7570b3", "#e7298a", "#66a61e", "#e6ab02", "#a6761d", "#666666"]
    good = [r for r in rows if r["peer"] == "clothsim" and r["status"] == "ok"]
    for i, (method, k) in enumerate(dict.fromkeys((r["method"], r["stiffness"]) for r in good)):
        style = ("p pt 9 ps 1.6" if method.startswith("symplectic") else
                 "lp pt 13 ps 1.1 dt 2" if "cgTolerance" in method else "lp pt 5 ps 1.2")
        series.append((f"clothsim {method}, {k} N/m", f"{style} lc rgb '{colours[i % len(colours)]}'",
                       [r for r in good if (r["method"], r["stiffness"]) == (method, k)]))
    series.append(("clothsim failed (exit 3, or steps failing their check)", "p pt 2 ps 2 lw 2 lc rgb 'red'",
                   [r for r in rows if r["peer"] == "clothsim" and r["status"] != "ok"]))
    series = [s for s in series if s[2]]
    with open(dat, "w") as f:
        for title, _, rs in series:
            f.write(f"# {title}\n")
            for r in rs:
                label = f"q{r['quality']}" if r["peer"] == "blender" else fraction(r["step_s"])
                if r["peer"] == "clothsim" and r["status"] != "ok":  # the failed series mixes stiffnesses
                    label += f",{float(r['stiffness']):.0e}".replace("e+0", "e") + ("L" if "maxStrain" in r["method"] else "")
                f.write(f"{chart_x(r)!r} {r['wall_s']!r} {r['cpu_s']!r} {label}\n")
            f.write("\n\n")
    terminals = subprocess.run(["gnuplot", "-e", "set terminal"], capture_output=True, text=True)
    have_png = "pngcairo" in terminals.stdout + terminals.stderr
    image = "peer_chart.png" if have_png else "peer_chart.svg"
    terminal = "pngcairo size 1400,820 font ',10'" if have_png else "svg size 1400,820"
    script = os.path.join(args.out, "peer_chart.gnuplot")

    def panel(column, what):
        plots = []
        for i, (title, style, _) in enumerate(series):
            plots.append(f"'{dat}' index {i} using 1:{column} with {style} title '{title}'")
            plots.append(f"'' index {i} using 1:{column}:4 with labels offset 1.2,0.6 font ',8' notitle")
        return (f"set ylabel '{what} (s, {frames / fps:g} s simulated)'\n"
                f"plot {', '.join(plots)}\n")

    with open(script, "w") as f:
        f.write(f"""set terminal {terminal}
set output '{os.path.join(args.out, image)}'
set multiplot layout 1,2 title "Peer sheet {side}x{side}, 1 m, 1 kg, two corners pinned: time against largest structural strain"
set logscale xy
set grid
set key outside below font ',8' maxcols 3 maxrows 6
set xlabel 'largest structural strain over the frames'
{panel(2, 'wall time')}
{panel(3, 'CPU time')}
unset multiplot
""")
    subprocess.run(["gnuplot", script], check=True)
    return image


def matches(rows):
    """For each Blender quality: the fastest good clothsim run (by wall time) within args.match x its strain, among
    all runs and among those solved to the first (strictest) CG tolerance, whose fall is the least damped."""
    good = [r for r in rows if r["peer"] == "clothsim" and r["status"] == "ok"]
    strict = [r for r in good if "cgTolerance" not in r["method"]]
    out = []
    if not good:
        return out

    def fastest(runs, b, prefix):
        within = [r for r in runs if r["max_strain"] <= args.match * b["max_strain"]]
        best = min(within, key=lambda r: r["wall_s"]) if within else min(runs, key=lambda r: r["max_strain"])
        return {f"{prefix}matched": "yes" if within else "no (the least-strained run shown)",
                f"{prefix}run": f"{best['method']} {best['stiffness']} N/m at {fraction(best['step_s'])} s",
                f"{prefix}strain": best["max_strain"], f"{prefix}wall_s": best["wall_s"], f"{prefix}sag_m": best["sag_m"],
                f"{prefix}wall_ratio": b["wall_s"] / best["wall_s"], f"{prefix}cpu_ratio": b["cpu_s"] / best["cpu_s"]}

    for b in (r for r in rows if r["peer"] == "blender" and r["status"] == "ok"):
        row = dict(quality=b["quality"], blender_strain=b["max_strain"], blender_wall_s=b["wall_s"],
                   blender_cpu_s=b["cpu_s"], blender_sag_m=b["sag_m"])
        row.update(fastest(good, b, "clothsim_"))
        if strict:
            row.update(fastest(strict, b, "strict_"))
        out.append(row)
    return out


def read_rows(path):
    """The rows of an earlier run's peer_chart.csv, numbers as numbers (--rows)."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for k in ("step_s", "wall_s", "cpu_s", "max_strain", "sag_m"):
            r[k] = float(r[k])
    return rows


def write_csv(path, rows, floats):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.{6 if k == 'step_s' else 4}g}" if k in floats and isinstance(v, float) else v)
                        for k, v in r.items()})


print(f"peer chart: {side} x {side} sheet, {frames / fps:g} s simulated, {args.threads} threads; load "
      f"{os.getloadavg()[0]:.2f} {os.getloadavg()[1]:.2f} {os.getloadavg()[2]:.2f} at the start", flush=True)
def run_all():
    """Every clothsim and Blender run the options ask for, one row each, printed as it ends."""
    rows = []

    def add(row):
        rows.append(row)
        print(row, flush=True)

    for tolerance in TOLERANCES:
        for word in args.stiffnesses.split(","):
            for n in args.steps.split(","):
                add(clothsim_row("implicit", word, 1.0 / float(n), tolerance=tolerance))
    for pair in filter(None, args.limited.split(",")):
        word, limit = pair.split("/")
        for n in args.limited_steps.split(","):
            add(clothsim_row("implicit", word, 1.0 / float(n), float(limit)))
    for word in filter(None, args.symplectic.split(",")):
        limit = symplectic_step(stiffness_of(word))
        add(clothsim_row("symplectic", word, 1.0 / (fps * int(np.ceil(1.0 / (fps * limit))))))
    for q in map(int, args.qualities.split(",")):
        add(blender_row(q))
    return rows


floats = {"step_s", "wall_s", "cpu_s", "max_strain", "sag_m", "load1", "blender_strain", "blender_wall_s",
          "blender_cpu_s", "blender_sag_m"}
floats |= {p + k for p in ("clothsim_", "strict_") for k in ("strain", "wall_s", "sag_m", "wall_ratio", "cpu_ratio")}
if args.rows:
    rows = read_rows(args.rows)
else:
    rows = run_all()
    write_csv(os.path.join(args.out, "peer_chart.csv"), rows, floats)
m = matches(rows)
if m:
    write_csv(os.path.join(args.out, "peer_chart_matches.csv"), m, floats)
image = write_chart(rows)
print(f"load {os.getloadavg()[0]:.2f} {os.getloadavg()[1]:.2f} {os.getloadavg()[2]:.2f} at the end; wrote "
      f"{args.out}/peer_chart.csv, peer_chart_matches.csv, {image}")
for r in m:
    print(r)
