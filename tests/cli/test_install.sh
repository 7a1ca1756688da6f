# cmake --install puts the library, headers, CLI and pkg-config file in place,
# and a program built against them with pkg-config renders a scene.
source "$(dirname "$0")/lib.sh"

build=$(dirname "$ORRERY")
cmake --install "$build" --prefix "$WORK/prefix" >install.log 2>&1 || fail "cmake --install: $(cat install.log)"
libdir=$(ls -d "$WORK"/prefix/lib*/pkgconfig | head -1)
[ -f "$libdir/orrery.pc" ] || fail "orrery.pc not installed"
[ -x "$WORK/prefix/bin/orrery" ] || fail "orrery CLI not installed"
[ -f "$WORK/prefix/include/orrery/render/render.h" ] || fail "headers not installed"
[ -f "$WORK/prefix/share/orrery/configs/first-light.yaml" ] || fail "configs not installed"

flags=""
grep -q "ORRERY_SANITIZE:BOOL=ON" "$build/CMakeCache.txt" && flags="-fsanitize=address,undefined"
export PKG_CONFIG_PATH="$libdir"
cc -std=c11 $flags "$SRC/examples/library/render_scene.c" $(pkg-config --cflags --libs orrery) \
  -o render_scene 2>cc.log || fail "building against the installed library: $(cat cc.log)"

printf 'x y z mass\n0 0 0 2\n0.5 0.5 0 3\n' >t.txt
write_scene s.yaml t.txt
LD_LIBRARY_PATH="$(dirname "$libdir")" ./render_scene s.yaml output.png=false >run.out 2>&1 || fail "render_scene failed: $(cat run.out)"
grep -q "weight in the image 5" run.out || fail "render_scene output: $(cat run.out)"
[ -f out/s.fits ] || fail "render_scene wrote no FITS"
[ -f out/s.png ] && fail "output.png=false not honoured"

finish
