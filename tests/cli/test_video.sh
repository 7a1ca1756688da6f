# orrery video encodes a scene's rendered frames (DIR/NAME_0000.png, ...)
# with ffmpeg. ffprobe, independent of orrery, reads back the frame count,
# size, rate and codec; decoded pixels are compared with the PNGs. Errors
# (a missing frame, no frames, no ffmpeg, an unwritable or existing output,
# ffmpeg failing) name what was wrong and leave no video or temporary file.
source "$(dirname "$0")/lib.sh"
py=/usr/bin/python3
[ -x "$py" ] || py=python3

# ffmpeg is a dependency (scripts/install-deps.sh installs it): fail, not skip.
for tool in ffmpeg ffprobe; do
  command -v "$tool" >/dev/null || { echo "FAIL: $tool not found (scripts/install-deps.sh installs ffmpeg)" >&2; exit 1; }
done

# probe FILE: reads the video's stream fields with ffprobe, counting the
# frames by decoding them; expect FIELD VALUE then checks one of them.
probed=""
probe() {
  probed=$1
  ffprobe -v error -count_frames -select_streams v:0 \
    -show_entries stream=codec_name,codec_tag_string,width,height,r_frame_rate,nb_read_frames,pix_fmt,color_space \
    -of default=noprint_wrappers=1 "$1" >probe.txt 2>&1 || fail "ffprobe $1: $(cat probe.txt)"
}
expect() {
  local got
  got=$(sed -n "s/^$1=//p" probe.txt)
  [ "$got" = "$2" ] || fail "$probed: $1 is '$got', expected '$2'"
}
# No video and no temporary file in DIR: only the frames.
only_frames_in() {
  local extra
  extra=$(ls -A "$1" | grep -v '\.png$' || true)
  [ -z "$extra" ] || fail "files left in $1: $extra"
}
# run_video CODE PATTERN -- args: expect exit CODE and stderr matching PATTERN.
run_video() {
  local code=$1 pattern=$2 got=0
  shift 3
  "$ORRERY" video "$@" >stdout.txt 2>stderr.txt || got=$?
  [ "$got" -eq "$code" ] || fail "orrery video $* exited $got, expected $code; stderr: $(cat stderr.txt)"
  grep -Eq -- "$pattern" stderr.txt || fail "orrery video $*: stderr does not match /$pattern/: $(cat stderr.txt)"
  if grep -q "AddressSanitizer\|runtime error" stderr.txt; then fail "orrery video $*: sanitizer report"; fi
}

cat >clip.yaml <<'EOT'
input:
  model:
    name: mw-m31
    particles: 3000
camera:
  projection: orthographic
  width: 80
image:
  width: 64
  height: 48
output:
  dir: out
  fits: false
EOT

# Three frames rendered by orrery itself, named as an animation's are.
for k in 0 1 2; do
  "$ORRERY" render --quiet clip.yaml --set output.name=clip_000$k --set camera.width=$((60 + 20 * k)) 2>err.txt ||
    fail "render frame $k: $(cat err.txt)"
done

# h264, the default: 3 frames, 64x48, 30 fps, an MP4 beside the frames.
"$ORRERY" video clip.yaml >stdout.txt 2>stderr.txt || fail "video h264: $(cat stderr.txt)"
grep -q "wrote out/clip.mp4: 3 frames of 64x48 at 30 fps, h264" stdout.txt || fail "h264 summary: $(cat stdout.txt)"
probe out/clip.mp4
expect codec_name h264
expect nb_read_frames 3
expect width 64
expect height 48
expect r_frame_rate 30/1
expect pix_fmt yuv420p
expect color_space bt709
[ -z "$(ls -A out | grep tmp)" ] || fail "temporary files left: $(ls -A out)"

# An existing video is kept unless --force.
run_video 1 "out/clip.mp4 exists \(--force replaces it\)" -- clip.yaml
"$ORRERY" video clip.yaml --force --quiet --fps 25 2>stderr.txt || fail "video --force: $(cat stderr.txt)"
probe out/clip.mp4
expect r_frame_rate 25/1

# ProRes master at 24 fps: a .mov, 4:2:2 10-bit, profile 3 (tag apch).
"$ORRERY" video clip.yaml --codec prores --fps 24 --quiet 2>stderr.txt || fail "video prores: $(cat stderr.txt)"
probe out/clip.mov
expect codec_name prores
expect codec_tag_string apch
expect nb_read_frames 3
expect width 64
expect height 48
expect r_frame_rate 24/1
expect pix_fmt yuv422p10le

# h265, tagged hvc1, NTSC rate, to a name of our choosing.
"$ORRERY" video clip.yaml --codec h265 --fps 30000/1001 --out "clip h265.mp4" --quiet 2>stderr.txt ||
  fail "video h265: $(cat stderr.txt)"
probe "clip h265.mp4"
expect codec_name hevc
expect codec_tag_string hvc1
expect nb_read_frames 3
expect r_frame_rate 30000/1001

# Frames with an odd size (33x17), a distinct colour each, in a folder and
# under a name with spaces and a '%' (which ffmpeg's own file patterns use): h264 pads them to 34x18 and says so; the
# decoded frames keep their order and colours (BT.709 both ways).
mkdir "odd dir"
"$py" - <<'EOT' || fail "writing the odd frames"
from PIL import Image
for k in range(4):
    Image.new("RGB", (33, 17), (40 + 50 * k, 160 - 30 * k, 90 + 30 * k)).save("odd dir/odd 100%% clip_%04d.png" % k)
EOT
cp clip.yaml odd.yaml
sed -i 's/^  dir: out/  dir: odd dir/' odd.yaml
"$ORRERY" video odd.yaml --set "output.name=odd 100% clip" >stdout.txt 2>stderr.txt || fail "video odd: $(cat stderr.txt)"
grep -q "padded to 34x18" stderr.txt || fail "odd size: no note of the padding: $(cat stderr.txt)"
probe "odd dir/odd 100% clip.mp4"
expect nb_read_frames 4
expect width 34
expect height 18
# decoded_pixel FILE FRAME: the RGB of pixel (10, 8) of that frame.
decoded_pixel() {
  ffmpeg -v error -nostdin -i "$1" -vf "select=eq(n\,$2)" -frames:v 1 -f rawvideo -pix_fmt rgb24 - |
    "$py" -c "import sys; d = sys.stdin.buffer.read(); w = int(sys.argv[1]); i = 3 * (8 * w + 10); print(*d[i:i + 3])" "$3"
}
for k in 0 3; do
  want="$((40 + 50 * k)) $((160 - 30 * k)) $((90 + 30 * k))"
  got=$(decoded_pixel "odd dir/odd 100% clip.mp4" $k 34)
  "$py" -c "import sys; a, b = sys.argv[1].split(), sys.argv[2].split(); sys.exit(0 if len(a) == 3 and all(abs(int(x) - int(y)) <= 3 for x, y in zip(a, b)) else 1)" "$got" "$want" ||
    fail "odd h264 frame $k: decoded colour '$got', the PNG's is '$want'"
done
# The png codec keeps the pixels exactly, at the odd size.
"$ORRERY" video odd.yaml --set "output.name=odd 100% clip" --codec png --quiet 2>stderr.txt || fail "video png: $(cat stderr.txt)"
probe "odd dir/odd 100% clip.mov"
expect codec_name png
expect width 33
[ "$(decoded_pixel "odd dir/odd 100% clip.mov" 2 33)" = "140 100 150" ] ||
  fail "png frame 2: decoded $(decoded_pixel "odd dir/odd 100% clip.mov" 2 33), the PNG's is 140 100 150"

# --frames N requires N frames and names the first missing one.
rm -f out/*.mp4 out/*.mov
run_video 1 "--frames 5: frame 3 is missing: out/clip_0003.png" -- clip.yaml --frames 5
only_frames_in out
"$ORRERY" video clip.yaml --frames 2 --quiet 2>stderr.txt || fail "video --frames 2: $(cat stderr.txt)"
probe out/clip.mp4
expect nb_read_frames 2
rm -f out/clip.mp4

# Without --frames, a gap ends the sequence, with a warning naming it.
cp out/clip_0002.png out/clip_0004.png
run_video 0 "warning: out/clip_0003.png is missing, so only frames 0 to 2 are encoded" -- clip.yaml --quiet
probe out/clip.mp4
expect nb_read_frames 3
rm -f out/clip.mp4 out/clip_0004.png

# No frames at all.
run_video 1 "no frames found: out/none_0000.png is missing" -- clip.yaml --set output.name=none
only_frames_in out

# Frames of different sizes cannot make one video.
"$py" -c "from PIL import Image; Image.new('RGB', (20, 10)).save('out/mixed_0000.png'); Image.new('RGB', (22, 10)).save('out/mixed_0001.png')"
run_video 1 "out/mixed_0001.png is 22x10 but frame 0 is 20x10" -- clip.yaml --set output.name=mixed
only_frames_in out

# ffmpeg failing (a frame with a PNG header but no image data) leaves nothing.
cp out/clip_0000.png out/broken_0000.png
head -c 40 out/clip_0001.png >out/broken_0001.png
run_video 1 "ffmpeg failed \(exit status [0-9]+\) writing out/broken.mp4" -- clip.yaml --set output.name=broken
only_frames_in out
rm -f out/broken_*.png out/mixed_*.png

# An output folder that does not exist.
run_video 1 "output directory no-such-dir: cannot create a file there" -- clip.yaml --out no-such-dir/clip.mp4
[ ! -e no-such-dir ] || fail "no-such-dir was created"

# No ffmpeg on the PATH.
got=0
env PATH=/nonexistent "$ORRERY" video clip.yaml 2>stderr.txt || got=$?
[ "$got" -eq 1 ] || fail "without ffmpeg: exit $got, expected 1"
grep -q "ffmpeg not found: install it (scripts/install-deps.sh installs it)" stderr.txt ||
  fail "without ffmpeg: $(cat stderr.txt)"
only_frames_in out

# Usage errors.
run_video 2 "--codec vp9: unknown codec" -- clip.yaml --codec vp9
run_video 2 "--crf applies to h264 and h265, not prores" -- clip.yaml --codec prores --crf 10
run_video 2 "--crf 52: expected a whole number from 0 to 51" -- clip.yaml --crf 52
run_video 2 "--fps 0: expected a rate above 0" -- clip.yaml --fps 0
run_video 2 "--out clip.mkv: a h264 video is a .mp4 file" -- clip.yaml --out clip.mkv
run_video 2 "--view dome: clip.yaml has no views" -- clip.yaml --view dome
run_video 2 "no scene file given" -- --codec h264
only_frames_in out

# Frame numbers of five digits (a run of over 10000 frames) are found too.
"$py" -c "
from PIL import Image
for k in range(3): Image.new('RGB', (16, 16), (80 * k, 0, 0)).save('out/long_%05d.png' % k)"
"$ORRERY" video clip.yaml --set output.name=long --codec png --quiet 2>stderr.txt || fail "video long: $(cat stderr.txt)"
probe out/long.mov
expect nb_read_frames 3
rm -f out/long*

# A scene with two views: both are checked before either video is made;
# --out needs --view.
cat >views.yaml <<'EOT'
input:
  model:
    name: mw-m31
    particles: 100
output:
  dir: views
views:
  near:
    output: {name: near}
  far:
    output: {name: far}
EOT
mkdir views
"$py" -c "
from PIL import Image
for k in range(2): Image.new('RGB', (16, 16)).save('views/near_%04d.png' % k)"
run_video 1 "no frames found: views/far_0000.png is missing" -- views.yaml
only_frames_in views
cp views/near_0000.png views/far_0000.png
run_video 2 "--out names one video, but views.yaml has 2 views: choose one with --view" -- views.yaml --out x.mp4
run_video 2 "--view middle: views.yaml has no such view \(its views: near, far\)" -- views.yaml --view middle
"$ORRERY" video views.yaml --codec png >stdout.txt 2>stderr.txt || fail "video views: $(cat stderr.txt)"
grep -q "view near: wrote views/near.mov: 2 frames" stdout.txt || fail "views: $(cat stdout.txt)"
grep -q "view far: wrote views/far.mov: 1 frame of 16x16" stdout.txt || fail "views: $(cat stdout.txt)"
"$ORRERY" video views.yaml --codec png --view far --out "far one.mov" --quiet 2>stderr.txt || fail "video --view far: $(cat stderr.txt)"
probe "far one.mov"
expect nb_read_frames 1

"$ORRERY" video --help | grep -q "usage: orrery video SCENE.yaml" || fail "video --help"
# Levels: frames that need H.264 level 6.0 get a warning (with --quiet
# too), those within 5.2 none; ffprobe reads the level x264 wrote, which is
# the one orrery computed. A frame 8704 pixels wide is 544 macroblocks, one
# more than level 5.2 takes on a side: level 6.0 as a 3600x3600 dome master
# is, at a fraction of the cost.
for size in 8688:51 8704:60; do
  w=${size%:*} level=${size#*:}
  rm -rf thin
  for k in 0 1; do
    "$ORRERY" render --quiet clip.yaml -o thin --set image.width=$w --set image.height=16 \
      --set output.name=thin_000$k 2>err.txt || fail "render thin frame $k: $(cat err.txt)"
  done
  "$ORRERY" video --quiet clip.yaml -o thin --set output.name=thin >stdout.txt 2>stderr.txt ||
    fail "video of ${w}x16: $(cat stderr.txt)"
  got=$(ffprobe -v error -select_streams v:0 -show_entries stream=level -of default=noprint_wrappers=1:nokey=1 thin/thin.mp4)
  [ "$got" = "$level" ] || fail "${w}x16: x264 wrote level $got, expected $level"
  if [ "$level" -gt 52 ]; then
    grep -q "^orrery: warning: ${w}x16 frames at 30 fps need h264 level 6.0, .*stop at level 5.2.*--codec prores" stderr.txt ||
      fail "${w}x16: no level warning: $(cat stderr.txt)"
  else
    [ -s stderr.txt ] && fail "${w}x16 (level $level): unexpected warning: $(cat stderr.txt)"
  fi
done

# A folder holding two runs' frames (rendered in pieces with --frames and
# other settings) is refused, naming the first frame made otherwise.
printf 'x y z mass\n0 0 0 1\n1 1 0 2\n' >mix.txt
write_scene mix.yaml mix.txt "animation:" "  frames: 4"
"$ORRERY" render mix.yaml -o mixed --frames 0:1 --set output.colormap=grey >/dev/null 2>&1 || fail "mix frames 0-1"
"$ORRERY" render mix.yaml -o mixed --frames 2:3 >/dev/null 2>&1 || fail "mix frames 2-3"
expect_fail 2 "frame 2 was made otherwise than frame 0 \(from frame 0 to frame 2: output.colormap=grey removed" none -- video mix.yaml -o mixed
[ ! -e mixed/mix.mp4 ] || fail "a video of a mix was written"
"$ORRERY" render mix.yaml -o mixed >/dev/null 2>&1 || fail "mix: the whole run"
"$ORRERY" video mix.yaml -o mixed --quiet >/dev/null 2>run.err || fail "video after the run was made whole: $(cat run.err)"

finish
