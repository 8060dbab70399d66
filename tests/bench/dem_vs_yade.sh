#!/usr/bin/env bash
# Side-by-side DEM throughput comparison with YADE on the bonded periodic lattice of the
# foundation issue. Runs, for each lattice size, anticrack with 1 and 2 threads and YADE with one
# thread, one after the other in this run, and prints the JSON lines plus the ratios.
# Needs: a built tree (scripts/setup) and the Debian package `yade` (apt-get install yade).
# Usage: tests/bench/dem_vs_yade.sh [n:steps ...]     default: 13:4000 30:400
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
anticrack=$root/build/app/anticrack
command -v yade >/dev/null || { echo "yade not installed (apt-get install yade)" >&2; exit 2; }
[ -x "$anticrack" ] || { echo "build first: scripts/setup" >&2; exit 2; }
cases=("$@")
[ ${#cases[@]} -gt 0 ] || cases=(13:4000 30:400)

for c in "${cases[@]}"; do
  n=${c%%:*}; steps=${c##*:}
  a1=$("$anticrack" bench dem --lattice "$n" --steps "$steps" --threads 1)
  a2=$("$anticrack" bench dem --lattice "$n" --steps "$steps" --threads 2)
  y=$(yade -j1 -n -x "$root/tests/bench/yade_lattice.py" --lattice "$n" --steps "$((steps / 4 > 0 ? steps / 4 : 1))" 2>/dev/null | grep '^{"code":"yade"' | tail -1)
  echo "$a1"; echo "$a2"; echo "$y"
  /usr/bin/python3 - "$a1" "$a2" "$y" <<'PY'
import json, sys
a1, a2, y = (json.loads(s) for s in sys.argv[1:4])
print(f"n = {round(a1['particles'] ** (1/3))}: bond-steps/s anticrack 1 thread {a1['bond_steps_per_s']:.3g}, "
      f"2 threads {a2['bond_steps_per_s']:.3g}, YADE 1 thread {y['bond_steps_per_s']:.3g}; "
      f"ratio 1T/YADE {a1['bond_steps_per_s'] / y['bond_steps_per_s']:.2f}, "
      f"2T/YADE {a2['bond_steps_per_s'] / y['bond_steps_per_s']:.2f}, "
      f"speed-up 1->2 threads {a2['bond_steps_per_s'] / a1['bond_steps_per_s']:.2f}")
PY
done
