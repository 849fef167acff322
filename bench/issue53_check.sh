#!/bin/bash
# Issue 53's cases (backward Euler in contact), re-run on the current build: one line per run with the figure the issue
# names, read from run.json (and from the stability study's CSV for momentum, and bench/self_intersections for folds).
# A measurement, not a test: it asserts nothing and exits 0 whatever the figures say (docs/energy.md, "Re-checking
# the contact cases"). Run from the project root after building; under two minutes of wall time on 2 cores.
#
#   bench/issue53_check.sh [BUILD_DIR]      (default: build)
#
#   (a) the free pair (scenes/jelly_shot.toml: 1.28 kg at 25 m/s into 25.6 kg, no gravity, no colliders; and at 10
#       and 5 m/s): momentum drift |p - p0| against p0 (sum m |v|, from the scene's keys: 32 kg m/s at 25 m/s), and
#       angular momentum drift, by `wobble study stability --contact free-pair` (default cg_tolerance), backward Euler
#       at 1/60 and 1/240 s, RK4 at the scene's 5e-4 s
#   (b) the default scene with jelly.ks = 1e7, backward Euler at 1/60 s (slope restitution 0.8): exit status, the
#       energy at start and end, whether the energy check fired, exact steps and retakes, simulate time
#   (c) bench/scenes/jelly_curtain.toml: a jelly at 150 m/s into a pinned cloth curtain, backward Euler at 1/60 s,
#       linearized (the default) and with newton = true
#   (d) bench/scenes/jelly_pile.toml: the six-jelly offset pile, backward Euler at 1/240 s: end_state.max_speed (the
#       largest particle speed over the last frame) at 4 s, 3 s after the top jelly has landed, and at 14 s
#   (e) bench/scenes/jelly_squeeze.toml: an elevator pressing a jelly 1.4 cm against a ceiling, every integrator at
#       1 ms and backward Euler at 1/60 and 1/240 s: exit status, energy rise against the elevator's counted work
#   (f) bench/scenes/jelly_well.toml: two soft jellies pressed in a narrow well, shipped defaults: each jelly's most
#       self-intersecting triangle pairs at any frame, backward Euler at 1/60 and 1/240 s, RK4 at 1/240 s; and with
#       self-contact off at 1/60 s, the control that shows the count sees folds
set -euo pipefail

build=${1:-build}
wobble=$build/wobble
for program in "$wobble" "$build/self_intersections"; do
  [[ -x $program ]] || { echo "issue53_check.sh: $program not found: build first (cmake --build $build)" >&2; exit 2; }
done
command -v python3 >/dev/null 2>&1 || { echo "issue53_check.sh: python3 is needed (run.json)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

h60=0.016666666666666666 h240=0.004166666666666667

# One line about a run: LABEL, its folder, its exit status and what to add (energy: start -> end; work: the colliders'
# counted work against the rise; rest: end_state.max_speed; plain: nothing).
summary() {
  python3 - "$@" <<'EOF'
import json, sys
label, out, status, what = sys.argv[1:5]
try:
    j = json.load(open(out + "/run.json"))
except OSError:
    print(f"{label}: exit {status}, no run.json"); sys.exit()
e, wall = j["energy"], j["wall_time_seconds"]["simulate"]
parts = [f"exit {status}", f"to {j['simulated_time']:.3g} s"]
if what in ("energy", "work"):
    parts.append(f"energy {e['start']:.4g} -> {e['end']:.4g} J")
if what == "work":
    rise = e["end"] - e["start"]
    work = e["collider_work"]
    parts.append(f"rise {rise:.3g} J, counted work {work:.3g} J (excess {rise - work:.2g} J)")
if what == "rest":
    parts.append(f"end_state.max_speed {j['end_state']['max_speed']:.3g} m/s (aim < 0.05)")
if j.get("gained_energy"):
    g = j["energy_gain"]
    parts.append(f"the energy check fired at step {g['step']}, t = {g['time']:.3g} s (gained {g['gained']:.4g} J, "
                 f"allowed {g['margin']:.4g})")
elif j.get("blew_up"):
    b = j["blow_up"]
    parts.append(f"blew up at step {b['step']}, t = {b['time']:.3g} s")
elif what in ("energy", "work"):
    parts.append("the energy check did not fire")
ls = j.get("linear_solver", {})
if ls.get("exact_steps") or e.get("retakes"):
    parts.append(f"{ls.get('exact_steps', 0)} exact steps, {e.get('retakes', 0)} retakes")
parts.append(f"simulate {wall:.2f} s")
print(f"{label}: " + ", ".join(p for p in parts if p))
EOF
}

# run LABEL WHAT SCENE [wobble run flags]: simulates without pictures or meshes into a folder of its own.
count=0
run() {
  local label=$1 what=$2 scene=$3 status=0
  shift 3
  count=$((count + 1))
  nice "$wobble" run "$scene" --render none --set output.obj=false --set output.pc2=false --out "$work/$count" "$@" \
    >"$work/$count.log" 2>&1 || status=$?
  summary "$label" "$work/$count" "$status" "$what"
}

echo "issue 53's cases on $(git rev-parse --short HEAD 2>/dev/null || echo '?'), $(date -u '+%F %H:%M UTC')"

# (a) Momentum of the free pair: the stability study's contact case, only it (a one-cell grid on the same scene), at
# the scene's 25 m/s and at the issue's slower hits (a copy of the scene with the bullet's speed changed).
for speed in 25 10 5; do
  shot=scenes/jelly_shot.toml
  if ((speed != 25)); then
    shot=$work/jelly_shot.toml
    sed "s/^velocity = \[25.0, 0.0, 0.0\]/velocity = [$speed.0, 0.0, 0.0]/" scenes/jelly_shot.toml >"$shot"
    grep -q "^velocity = \[$speed.0, 0.0, 0.0\]" "$shot" ||
      { echo "(a) free pair at $speed m/s: skipped, the scene's velocity line was not found"; continue; }
  fi
  nice "$wobble" study stability "$shot" --contact-scene free-pair="$shot" --integrators backward-euler,rk4 \
    --contact free-pair --ks-points 1 --dt-points 1 --ks-min 2000 --ks-max 2000 --dt-min $h60 --dt-max $h60 \
    --gnuplot true --out "$work/study$speed" >"$work/study$speed.log" 2>&1 ||
    { echo "(a) the stability study failed at $speed m/s:"; tail -3 "$work/study$speed.log"; }
  python3 - "$work/study$speed/stability.csv" "$speed" "$shot" <<'EOF' || true
import csv, math, sys, tomllib
rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["contact_case"] == "free-pair"]
speed = float(sys.argv[2])
# The study's scale of the drift, sum m |v| (the bullet's momentum: the target starts at rest), from the scene's keys:
# a cube jelly has n^3 particles of `mass` each.
p0 = 0.0
for name, body in tomllib.load(open(sys.argv[3], "rb"))["bodies"].items():
    if body.get("type") != "jelly" or "mesh" in body or "n" not in body or "mass" not in body:
        print(f"(a) free pair at {speed:g} m/s: skipped, body '{name}' is not a cube jelly with its n and mass set")
        sys.exit()
    p0 += body["n"] ** 3 * body["mass"] * math.hypot(*body.get("velocity", (0.0, 0.0, 0.0)))
for integrator, dt, name in (("backward-euler", 1 / 60, "1/60"), ("backward-euler", 1 / 240, "1/240"),
                             ("rk4", 5e-4, "5e-4")):
    for r in rows:
        if r["integrator"] == integrator and abs(float(r["dt"]) - dt) < 1e-9:
            p = float(r["momentum_drift"])
            print(f"(a) free pair at {speed:g} m/s, {integrator} at {name} s: {r['outcome']} to "
                  f"{float(r['end_time']):.3g} s, momentum off by {100 * p:.3g}% (|p - p0| {p0 * p:.3g} of "
                  f"{p0:.3g} kg m/s; aim 0.1%), angular momentum drift {100 * float(r['angular_momentum_drift']):.3g}%")
EOF
done

# (b) The stiff default scene.
run "(b) default scene, jelly.ks 1e7, backward-euler at 1/60 s" energy scenes/jelly_slope.toml \
  --integrator backward-euler --dt $h60 --set jelly.ks=1e7

# (c) The throw into the curtain.
run "(c) jelly at 150 m/s into a curtain, backward-euler at 1/60 s" energy bench/scenes/jelly_curtain.toml
run "(c) the same with newton = true" energy bench/scenes/jelly_curtain.toml --set simulation.newton=true

# (d) The six-jelly pile: 3 s after the top one lands, and where the issue looked (14 s).
# (Frame k shows (k - 1) / fps: a duration of T + 1/60 s puts the last frame at T.)
for end in 4.0166666666666667 14.016666666666667; do
  run "(d) six-jelly pile, backward-euler at 1/240 s" rest bench/scenes/jelly_pile.toml --set simulation.duration=$end
done

# (e) The squeeze, every integrator.
for integrator in explicit-euler symplectic-euler pc-euler midpoint rk4 rk45 backward-euler; do
  run "(e) squeeze, $integrator at 1 ms" work bench/scenes/jelly_squeeze.toml --integrator $integrator --dt 0.001
done
for dt in $h60 $h240; do
  run "(e) squeeze, backward-euler at 1/$(python3 -c "print(round(1 / $dt))") s" work bench/scenes/jelly_squeeze.toml \
    --integrator backward-euler --dt "$dt"
done

# (f) The well: folds with the shipped defaults (self-contact on for jellies among other bodies).
# The last run is the control: self-contact off, the folds the counter must see (the issue counted 117-264 pairs).
# At 1/60 s the scene's own step (0.0166666666666667, as the self-contact test runs it).
well60=0.0166666666666667
for spec in "backward-euler $well60 1/60" "backward-euler $h240 1/240" "rk4 $h240 1/240" \
  "backward-euler $well60 1/60 off"; do
  read -r integrator dt name off <<<"$spec"
  sets=(--set output.obj=false)
  [[ -n $off ]] && sets+=(--set bodies.low.self_contact=false --set bodies.high.self_contact=false)
  count=$((count + 1))
  status=0
  nice "$build/self_intersections" bench/scenes/jelly_well.toml --integrator "$integrator" --dt "$dt" \
    "${sets[@]}" --out "$work/$count" >"$work/$count.log" 2>"$work/$count.err" || status=$?
  folds=$(sed -nE 's/^(low|high): at most ([0-9]+) .*, ([0-9]+) of ([0-9]+) frames.*/\1 \2 (\3 of \4 frames)/p' \
    "$work/$count.log" | paste -sd, - | sed 's/,/, /g')
  label="(f) well, $integrator at $name s${off:+, control: self-contact off}"
  summary "$label: most self-intersecting pairs in a frame: ${folds:-none counted} (aim ${off:+> }0)" \
    "$work/$count" $status plain
done
