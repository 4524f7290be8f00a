"""Peer side by side: the same sheet (1 m square, 1 kg, hanging from the two corners of one
edge, starting flat) for the same simulated time in Blender's cloth modifier, baked headless, and in clothsim,
in one run, on one machine.

  blender -b --factory-startup --python-exit-code 1 --python bench/peer_blender.py -- CLOTHSIM_BIN SCRATCH_DIR \
      [--side 128] [--seconds 1] [--fps 24] [--quality 5] [--tension 15] [--integrator implicit] \
      [--stiffness N_PER_M] [--timestep 0.0041667] [--cg-tolerance 1e-3] [--max-strain 0.1] [--threads 2] \
      [--preconditioner jacobi|multigrid]

bench/peer_blender.sh wraps it and exits 77 (skipped) where blender is not installed. Prints one row per peer:
the step, simulated seconds per wall second and per CPU second, particle-steps per CPU second, the largest strain of
the structural edges over the frames, and the ratio of each rate to clothsim's. docs/performance.md ("Peers side
by side") explains the model differences.

Matched model: assuming Blender's spring constant is tension / (average spring length), clothsim gets stiffness =
tension * (side - 1) N/m per spring unless --stiffness is given (Blender counts time in frames, so its springs are
that times fps^2 in N/m: bench/peer_blender_motion.py and docs/accuracy.md give the figures), the same 1 kg spread
over side^2 vertices, and gravity 9.81 m/s^2. Blender's bending (angular) and damping models differ
from clothsim's springs; both are left at values that keep each sheet stable.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from peer_run import run_clothsim_timed  # noqa: E402
from peer_sheet import bake_blender, write_clothsim_scene  # noqa: E402

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
ap = argparse.ArgumentParser(prog="peer_blender.py")
ap.add_argument("clothsim", help="path to the clothsim binary")
ap.add_argument("scratch", help="folder for the bake, the clothsim scene and its frames")
ap.add_argument("--side", type=int, default=128, help="vertices along each side")
ap.add_argument("--seconds", type=float, default=1.0, help="simulated time")
ap.add_argument("--fps", type=int, default=24)
ap.add_argument("--quality", type=int, default=5, help="Blender's quality steps (substeps per frame)")
ap.add_argument("--tension", type=float, default=15.0, help="Blender tension/shear stiffness (its default 15)")
ap.add_argument("--stiffness", type=float, default=0.0,
                help="clothsim stiffness, N/m per spring (default: Blender's tension * (side - 1))")
ap.add_argument("--integrator", default="implicit", help="clothsim integrator")
ap.add_argument("--timestep", type=float, default=1.0 / 240, help="clothsim step, s")
ap.add_argument("--cg-tolerance", type=float, default=1e-3, help="clothsim implicit: relative CG residual")
ap.add_argument("--max-strain", type=float, default=0.0,
                help="clothsim: Provot strain limit (the cloth's maxStrain), e.g. 0.1; default none")
ap.add_argument("--threads", type=int, default=2, help="threads for both")
ap.add_argument("--preconditioner", default="",
                help="clothsim implicit: the CG's preconditioner, jacobi or multigrid (default: the scene default)")
args = ap.parse_args(argv)

side, fps = args.side, args.fps
frames = round(args.seconds * fps)
seconds = frames / fps
particles = side * side
os.makedirs(args.scratch, exist_ok=True)


def run_blender():
    return bake_blender(side, fps, frames, args.quality, args.tension, args.threads)


def run_clothsim():
    # Blender's k = tension / rest length, rest = 1 m / (side - 1), unless given.
    stiffness = args.stiffness if args.stiffness > 0 else args.tension * (side - 1)
    out = os.path.join(args.scratch, "clothsim_out")
    xml = os.path.join(args.scratch, "peer_sheet.xml")
    stats = os.path.join(args.scratch, "peer_stats.json")
    write_clothsim_scene(xml, out, side, fps, frames, args.integrator, args.timestep, stiffness, args.cg_tolerance,
                         args.max_strain, args.preconditioner)
    wall, cpu, st = run_clothsim_timed(args.clothsim, xml, args.threads, stats)
    # The whole process, loading and writing frames included, as Blender's bake includes its set-up.
    return dict(peer=f"clothsim {st['integrator']}", step=st["dt"], steps=st["steps"], wall=wall, cpu=cpu,
                max_strain=max(fr["max_strain"] for fr in st["frames"]), finite=st["status"] == "ok",
                stiffness=stiffness, cg_iterations=st.get("cg_iterations", 0),
                preconditioner=st.get("preconditioner", ""),
                strain_iterations=st.get("strain_limit_iterations", 0))


cs = run_clothsim()
bl = run_blender()
print(f"{side} x {side} sheet, 1 m, 1 kg, two corners pinned, {seconds:g} s simulated, {args.threads} threads; "
      f"Blender quality {args.quality}, tension {args.tension:g} (clothsim stiffness {cs['stiffness']:g} N/m)")
print(f"{'peer':<18} {'step_s':>10} {'steps':>6} {'wall_s':>8} {'cpu_s':>8} {'sim_s/wall_s':>12} "
      f"{'sim_s/cpu_s':>11} {'pst/cpu_s':>13} {'max_strain':>10} {'cs_vs_peer_wall':>15} {'cs_vs_peer_cpu':>14}")
for r in (cs, bl):
    print(f"{r['peer']:<18} {r['step']:>10.4g} {r['steps']:>6d} {r['wall']:>8.3f} {r['cpu']:>8.3f} "
          f"{seconds / r['wall']:>12.4f} {seconds / r['cpu']:>11.4f} {particles * r['steps'] / r['cpu']:>13.4g} "
          f"{r['max_strain']:>10.4f} {r['wall'] / cs['wall']:>15.2f} {r['cpu'] / cs['cpu']:>14.2f}"
          f"{'' if r['finite'] else '  (diverged)'}")
if cs["cg_iterations"] or cs["strain_iterations"]:
    print(f"clothsim: {cs['cg_iterations'] / cs['steps']:.1f} CG iterations a step ({cs['preconditioner']}), "
          f"{cs['strain_iterations'] / cs['steps']:.1f} strain-limit sweeps a step")
