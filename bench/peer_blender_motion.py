"""Why Blender's peer sheet hardly moves: the peer sheet (bench/peer_sheet.py: 1 m square, 1 kg, two corners of
one edge pinned, starting flat) baked in Blender's cloth modifier under settings that isolate each cause, with
the mean fall of its vertices at the last frame and its largest structural strain.

  blender -b --factory-startup --python-exit-code 1 --python bench/peer_blender_motion.py -- \\
      [--side 128] [--seconds 0.5] [--fps 24] [--quality 5] [--tension 15] [--threads 2]

Blender's cloth solver counts time in frames and scales the scene's gravity by 0.001 (its implicit solver's
force set-up), so a sheet falls under 0.001 fps^2 g: 0.576 g at 24 fps. "g matched" rows set the scene's gravity
to 9.81 / (0.001 fps^2) so that it falls under 9.81 m/s^2 as clothsim's does. The heavy rows make the sheet
--heavy kg, which leaves a free fall unchanged; "tension scaled" keeps its stiffness-to-weight ratio, so that a
solve of the same equations moves it exactly as the 1 kg sheet. docs/accuracy.md ("Peer chart") gives the figures.
"""
import argparse
import sys
import os

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from peer_sheet import bake_blender  # noqa: E402

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
args = ap.parse_args(argv)

frames = round(args.seconds * args.fps)
seconds = frames / args.fps
matched = 9.81 / (0.001 * args.fps ** 2)
undamped = {name: 0.0 for name in ("air_damping", "tension_damping", "compression_damping", "shear_damping",
                                   "bending_damping")}
rows = [
    ("as the peer chart bakes it (Blender's defaults)", dict()),
    ("every damping 0", dict(settings=undamped)),
    ("every damping 0, g matched", dict(settings=undamped, gravity=matched)),
    (f"every damping 0, g matched, {args.heavy:.1f} kg", dict(settings=undamped, gravity=matched, mass=args.heavy)),
    (f"the same, tension {args.tension * args.heavy:.0f}",
     dict(settings=undamped, gravity=matched, mass=args.heavy, tension=args.tension * args.heavy)),
    ("corners free, every damping 0, g matched", dict(settings=undamped, gravity=matched, pinned=False)),
    (f"corners free, every damping 0, g matched, {args.heavy:.1f} kg",
     dict(settings=undamped, gravity=matched, mass=args.heavy, pinned=False)),
]
print(f"{args.side} x {args.side} sheet, 1 m, {seconds:g} s simulated, Blender quality {args.quality}, tension "
      f"{args.tension:g}, {args.fps} fps; g matched = scene gravity {matched:.3f} m/s^2; a free fall under "
      f"9.81 m/s^2 drops {0.5 * 9.81 * seconds ** 2:.3f} m")
print(f"{'bake':<56} {'mean fall, m':>12} {'largest strain':>14} {'wall, s':>8}")
for label, kw in rows:
    kw.setdefault("tension", args.tension)
    r = bake_blender(args.side, args.fps, frames, args.quality, threads=args.threads, **kw)
    print(f"{label:<56} {r['sag']:>12.4f} {100 * r['max_strain']:>13.3f}% {r['wall']:>8.2f}"
          f"{'' if r['finite'] else '  (diverged)'}")
