# Input that can be read only once: "-" (standard input), pipes such as
# <(...), and FIFOs. Format detection keeps the bytes it looks at for the
# reader (it used to consume them: "no header line"); only text can be read
# from a stream, the binary formats (which seek) are refused naming the file
# and saying it must be a regular file; a FIFO with no writer fails at once
# instead of blocking forever (every run is under `timeout 10`).
source "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
[ -x "$py" ] || py=python3
# Every orrery run of this script, expect_fail's included, under a timeout.
printf '#!/bin/sh\nexec timeout 10 "%s" "$@"\n' "$ORRERY" >orrery10
chmod +x orrery10
ORRERY=$WORK/orrery10

# A table longer than the 4096 bytes detection peeks at: 500 rows, masses
# 0..499 (sum 124750), so rows are cut at the peek's end.
{ echo "x y z mass"; for i in $(seq 0 499); do echo "$i.125 -$i.5 0.25 $i"; done; } >table.txt
"$py" "$SRC/tests/cli/make_snapshot.py" gadget snap.gdt || fail "make_snapshot.py"
write_scene stdin.yaml '"-"' # quoted: a bare - is a YAML list entry

expect_count() { # expect_count LABEL: info output in info.txt names 500 particles, mass 124750
  grep -Eq "^particles: *500\b" info.txt || fail "$1: not 500 particles: $(cat info.txt)"
  grep -Eq "124750" info.txt || fail "$1: mass total not 124750: $(cat info.txt)"
}

"$ORRERY" info - <table.txt >info.txt 2>err.txt || fail "info - < table.txt: $(cat err.txt)"
expect_count "info - (redirected file)"
cat table.txt | "$ORRERY" info - >info.txt 2>err.txt || fail "cat | info -: $(cat err.txt)"
expect_count "cat | info -"
"$ORRERY" info <(cat table.txt) >info.txt 2>err.txt || fail "info <(cat table.txt): $(cat err.txt)"
expect_count "info <(cat table.txt)"
cat table.txt | "$ORRERY" render stdin.yaml >out.txt 2>err.txt || fail "cat | render (input.file: -): $(cat err.txt)"
[ -f out/stdin.png ] || fail "render from standard input wrote no out/stdin.png"
grep -q "read 500 particles" out.txt || fail "render from standard input: $(cat out.txt)"

# Binary formats need a regular file, detected or named.
expect_fail 2 "standard input: holds a gadget file, and gadget files are read with seeks, so the input must be a regular file, but this is standard input" none -- info - <snap.gdt
expect_fail 2 "/dev/fd/[0-9]+: holds a gadget file, and gadget files are read with seeks, so the input must be a regular file, but this is a pipe or FIFO" none -- info <(cat snap.gdt)
expect_fail 2 "/dev/fd/[0-9]+: gadget files are read with seeks, so the input must be a regular file" none -- \
  info --format gadget <(cat snap.gdt)
expect_fail 2 "standard input: tipsy files are read with seeks, so the input must be a regular file" none -- \
  info --format tipsy - <table.txt

# A FIFO with no writer: an error at once, for text as for binary formats.
mkfifo fifo
expect_fail 1 "fifo: no data \(a pipe or FIFO\): no program had it open for writing" none -- info fifo
expect_fail 2 "fifo: hdf5 files are read with seeks, so the input must be a regular file, but this is a pipe or FIFO" none -- \
  info fifo --format hdf5
# render too: its resume marker's checksum of the input must not open the
# FIFO and wait for a writer (a still and an animation both).
write_scene fifo.yaml fifo
expect_fail 1 "^orrery: error: fifo: no data \(a pipe or FIFO\)" fifo-out -- render fifo.yaml -o fifo-out
expect_fail 1 "^orrery: error: frame 0: fifo: no data \(a pipe or FIFO\)" fifo-out -- render fifo.yaml -o fifo-out --set animation.frames=2
# With a writer waiting (it blocks in open until orrery opens the FIFO).
cat table.txt >fifo &
writer=$!
sleep 1
"$ORRERY" info fifo >info.txt 2>err.txt || fail "info fifo with a writer: $(cat err.txt)"
expect_count "info fifo"
kill "$writer" 2>/dev/null
wait "$writer" 2>/dev/null

finish
