#!/bin/bash
# The benchmark's snapshot generator (bench_snapshot): orrery reads the
# files it writes with the right count and total mass (the built-in model's
# documented component masses, docs/model.md; 1 for the Plummer sphere), every
# HSML is positive, and HSML = r_32, the distance to the 32nd neighbour
# (h = 0.5 r_32, written as Gadget's 2h), checked against a brute-force
# search for a few particles. Bad arguments and an unwritable path fail with
# a message and leave no file.
#   test_bench_snapshot.sh ORRERY BENCH_SNAPSHOT
set -u
ORRERY=$1
GEN=$2
WORK=$(mktemp -d /tmp/orrery-bench-snapshot-XXXXXX)
trap 'rm -rf "$WORK"' EXIT
cd "$WORK" || exit 1
failures=0
fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
n=10000

# floats FILE OFFSET COUNT: COUNT little-endian floats from byte OFFSET, one a line.
floats() { od -An -v -w4 -f --endian=little -j "$2" -N $((4 * $3)) "$1" | awk '{ print $1 }'; }
# The data of the blocks (each in 4-byte record markers): header 256 bytes,
# POS 12n, VEL 12n, ID 4n, MASS 4n, U 4n, RHO 4n, HSML 4n.
pos_at=$((264 + 4))
hsml_at=$((264 + 2 * (12 * n + 8) + 4 * (4 * n + 8) + 4))

check_model() { # MODEL TOTAL-MASS
  local model=$1 total=$2 info
  "$GEN" "$model" $n "$model.g" >gen.log 2>&1 || { fail "$model: bench_snapshot: $(cat gen.log)"; return; }
  [ -f "$model.g.tmp" ] && fail "$model: temporary file left"
  [ "$(stat -c %s "$model.g")" -eq $((hsml_at + 4 * n + 4)) ] || fail "$model: file size $(stat -c %s "$model.g")"
  info=$("$ORRERY" info "$model.g") || { fail "$model: orrery info failed"; return; }
  grep -q "^particles:  $n\$" <<<"$info" || fail "$model: count: $(grep particles: <<<"$info")"
  grep -q "^  type 0:   $n particles" <<<"$info" || fail "$model: not all gas"
  grep -q "^fields:.* h " <<<"$info" || fail "$model: no smoothing lengths"
  awk -v want="$total" '/^mass:/ { m = $3 } END { d = (m - want) / want; exit !(d < 1e-5 && d > -1e-5) }' <<<"$info" ||
    fail "$model: total mass $(grep ^mass: <<<"$info"), expected $total"
  floats "$model.g" $hsml_at $n >hsml.txt
  awk -v n=$n 'NR == 1 || $1 < min { min = $1 } END { exit !(NR == n && min > 0) }' hsml.txt ||
    fail "$model: $(wc -l <hsml.txt) HSML values, smallest $(sort -g hsml.txt | head -1)"
  # Brute force: r_32 of the first 5 particles against all n.
  floats "$model.g" $pos_at $((3 * n)) | paste - - - >pos.txt
  for i in 1 2 3 4 5; do
    r=$(awk -v i=$i 'NR == i { x = $1; y = $2; z = $3 } { px[NR] = $1; py[NR] = $2; pz[NR] = $3 }
      END { for (j = 1; j <= NR; j++) if (j != i) printf "%.9g\n", sqrt((px[j] - x)^2 + (py[j] - y)^2 + (pz[j] - z)^2) }' pos.txt |
      sort -g | sed -n 32p)
    h=$(sed -n ${i}p hsml.txt)
    # Float positions are exact only to ~1e-7 of their distance from the
    # origin (M31's centre is 780 kpc out): the k-d tree's float arithmetic
    # may move r_32 by a few of those units, besides 1e-5 relative.
    far=$(awk -v i=$i 'NR == i { printf "%.9g\n", sqrt($1^2 + $2^2 + $3^2) }' pos.txt)
    awk -v r="$r" -v h="$h" -v far="$far" 'BEGIN { d = h - r; tol = 1e-5 * r + 4.8e-7 * far;
      exit !(r > 0 && d < tol && d > -tol) }' ||
      fail "$model: particle $i: HSML $h, r_32 by brute force $r"
  done
}
check_model pair 265.5144
check_model plummer 1

# Bad input: a message, a non-zero exit, no file.
expect_error() { # PATTERN ARGS...
  local pattern=$1 got=0
  shift
  "$GEN" "$@" >out.txt 2>err.txt || got=$?
  [ "$got" -ne 0 ] || fail "bench_snapshot $* succeeded"
  grep -Eq -- "$pattern" err.txt || fail "bench_snapshot $*: stderr does not match /$pattern/: $(cat err.txt)"
}
expect_error "N '10': expected a whole number from 100" pair 10 bad.g
expect_error "usage" galaxy 1000 bad.g
expect_error "--k '-3'" plummer 1000 bad.g --k -3
expect_error "nowhere/bad.g" plummer 1000 nowhere/bad.g
[ -z "$(ls bad.g* nowhere 2>/dev/null)" ] || fail "files left after errors: $(ls bad.g* nowhere 2>/dev/null)"

if [ "$failures" -ne 0 ]; then
  echo "$failures failed" >&2
  exit 1
fi
echo "all passed"
