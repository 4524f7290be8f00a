"""Why Blender's peer sheet hardly moves: the peer sheet (bench/peer_sheet.py: 1 m square, 1 kg, two corners of
one edge pinned, starting flat) baked in Blender's cloth modifier under settings that isolate each cause, with
the mean fall of its vertices at the last frame and its largest structural strain.

  blender -b --factory-startup --python-exit-code 1 --python bench/peer_blender_motion.py -- \\
      [--side 128] [--seconds 0.5] [--fps 24] [--quality 5] [--tension 15] [--threads 2] \\
      [--clothsim build/clothsim --scratch DIR [--repeats 3]]

Blender's cloth solver counts time in frames and scales the scene's gravity by 0.001 (its implicit solver's
force set-up), so a sheet falls under 0.001 fps^2 g: 0.576 g at 24 fps. "g matched" rows set the scene's gravity
to 9.81 / (0.001 fps^2) so that it falls under 9.81 m/s^2 as clothsim's does. The heavy rows make the sheet
--heavy kg, which leaves a free fall unchanged; "tension scaled" keeps its stiffness-to-weight ratio, so that a
solve of the same equations moves it exactly as the 1 kg sheet. docs/accuracy.md ("Peer chart") gives the figures.

With --clothsim, the heavy sheet that Blender does swing is set beside clothsim's equivalent, side by side, each
--repeats times, medians: clothsim's 1 kg sheet with springs of tension (side - 1) fps^2 / heavy N/m (Blender's
spring tension / rest length, in its frame time, per kg of sheet), no damping, bend 0.001 of the stiffness, implicit
at Blender's quality step 1 / (fps quality), CG tolerance 1e-3.
"""
import argparse
import os
import statistics
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from peer_run import run_clothsim_timed  # noqa: E402
from peer_sheet import (UNDAMPED, backward_euler_fall, bake_blender, grid_edges, matched_gravity,  # noqa: E402
                        read_obj, structural_strain, write_clothsim_scene)

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
ap = argparse.ArgumentParser(prog="peer_blender_motion.py")
ap.add_argument("--side", type=int, default=128, help="vertices along each side")
ap.add_argument("--seconds", type=float, default=0.5, help="simulated time")
ap.add_argument("--fps", type=int, default=24)
ap.add_argument("--quality", type=int, default=5, help="Blender's quality steps (substeps per frame)")
ap.add_argument("--tension", type=float, default=15.0, help="Blender tension/shear stiffness (its default 15)")
ap.add_argument("--threads", type=int, default=2)
ap.add_argument("--heavy", type=float, default=10000.0 / 15,
                help="the heavy rows' mass, kg (default: the heaviest sheet whose tension, scaled with its mass, "
                     "stays within the 10,000 Blender accepts)")
ap.add_argument("--clothsim", help="clothsim binary: also run its equivalent of the heavy swinging sheet")
ap.add_argument("--scratch", default="/tmp/peer_motion", help="folder for clothsim's scene and frames")
ap.add_argument("--repeats", type=int, default=3, help="side-by-side repeats of that pair")
args = ap.parse_args(argv)

frames = round(args.seconds * args.fps)
seconds = frames / args.fps
matched = matched_gravity(args.fps)
steps, step = frames * args.quality, 1.0 / (args.fps * args.quality)
# The heavy sheet Blender does swing, at the peer sheet's tension: a row below, and --clothsim's pair.
heavy = dict(settings=UNDAMPED, gravity=matched, mass=args.heavy, tension=args.tension)
rows = [
    ("as the peer chart bakes it (Blender's defaults)", dict()),
    ("every damping 0", dict(settings=UNDAMPED)),
    ("every damping 0, g matched", dict(settings=UNDAMPED, gravity=matched)),
    (f"every damping 0, g matched, {args.heavy:.1f} kg", heavy),
    (f"the same, tension {args.tension * args.heavy:.0f}",
     dict(settings=UNDAMPED, gravity=matched, mass=args.heavy, tension=args.tension * args.heavy)),
    ("corners free, every damping 0, g matched", dict(settings=UNDAMPED, gravity=matched, pinned=False)),
    (f"corners free, every damping 0, g matched, {args.heavy:.1f} kg",
     dict(settings=UNDAMPED, gravity=matched, mass=args.heavy, pinned=False)),
]
print(f"{args.side} x {args.side} sheet, 1 m, {seconds:g} s simulated, Blender quality {args.quality}, tension "
      f"{args.tension:g}, {args.fps} fps; g matched = scene gravity {matched:.3f} m/s^2; a free fall under "
      f"9.81 m/s^2 drops {0.5 * 9.81 * seconds ** 2:.3f} m ({backward_euler_fall(9.81, steps, step):.4f} m in "
      f"Blender's {steps} backward-Euler steps)")
print(f"{'bake':<56} {'mean fall, m':>12} {'largest strain':>14} {'wall, s':>8}")
for label, kw in rows:
    r = bake_blender(args.side, args.fps, frames, args.quality, threads=args.threads, **{"tension": args.tension, **kw})
    print(f"{label:<56} {r['sag']:>12.4f} {100 * r['max_strain']:>13.3f}% {r['wall']:>8.2f}"
          f"{'' if r['finite'] else '  (diverged)'}")

if args.clothsim:
    os.makedirs(args.scratch, exist_ok=True)
    stiffness = args.tension * (args.side - 1) * args.fps ** 2 / args.heavy
    xml, stats = os.path.join(args.scratch, "sheet.xml"), os.path.join(args.scratch, "stats.json")
    pattern = write_clothsim_scene(xml, os.path.join(args.scratch, "out"), args.side, args.fps, frames, "implicit",
                                   step, stiffness, damping=0.0, air_damping=0.0,
                                   bend=0.001)
    walls_b, walls_c = [], []
    for _ in range(args.repeats):
        b = bake_blender(args.side, args.fps, frames, args.quality, threads=args.threads, **heavy)
        walls_b.append(b["wall"])
        walls_c.append(run_clothsim_timed(args.clothsim, xml, args.threads, stats)[0])
    first = read_obj(pattern.format(1))[0]
    edges = grid_edges(args.side)
    rest = np.linalg.norm(first[edges[:, 1]] - first[edges[:, 0]], axis=1)
    strain = max(structural_strain(read_obj(pattern.format(f))[0], edges, rest) for f in range(2, 2 + frames))
    fall = float((first[:, 1] - read_obj(pattern.format(1 + frames))[0][:, 1]).mean())
    wb, wc = statistics.median(walls_b), statistics.median(walls_c)
    print(f"\nthe swinging sheet side by side, {args.repeats} runs each, median walls:")
    print(f"  Blender, {args.heavy:.1f} kg, tension {args.tension:g}: fall {b['sag']:.4f} m, largest strain "
          f"{100 * b['max_strain']:.2f}%, wall {wb:.2f} s")
    print(f"  clothsim, 1 kg, {stiffness:.1f} N/m, step {step:.5g} s: fall {fall:.4f} m, "
          f"largest strain {100 * strain:.2f}%, wall {wc:.2f} s; Blender / clothsim wall {wb / wc:.2f}")
