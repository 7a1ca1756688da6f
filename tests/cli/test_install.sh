# cmake --install puts the library, the public header, CLI and pkg-config
# file in place; a program built against them with pkg-config and the
# documented #include <orrery/orrery.h> renders a scene; the shared library
# exports only orr_* and orrery_* symbols.
source "$(dirname "$0")/lib.sh"

build=$(dirname "$ORRERY")
cmake --install "$build" --prefix "$WORK/prefix" >install.log 2>&1 || fail "cmake --install: $(cat install.log)"
libdir=$(ls -d "$WORK"/prefix/lib*/pkgconfig | head -1)
[ -f "$libdir/orrery.pc" ] || fail "orrery.pc not installed"
[ -x "$WORK/prefix/bin/orrery" ] || fail "orrery CLI not installed"
[ -f "$WORK/prefix/include/orrery/orrery.h" ] || fail "orrery.h not installed"
# Only the public headers: the in-situ API and, with MPI, its extension.
extra=$(cd "$WORK/prefix/include/orrery" && find . -name '*.h' | grep -v '^\./orrery\.h$\|^\./mpi/orrery_mpi\.h$' || true)
[ -z "$extra" ] || fail "internal headers installed: $(echo $extra | head -c 300)"
so=$(ls "$(dirname "$libdir")"/liborrery.so.* | head -1)
others=$(nm -D --defined-only "$so" | awk '$2 != "A" {sub(/@.*/, "", $3); print $3}' | grep -v '^orr_\|^orrery_' || true)
[ -z "$others" ] || fail "liborrery.so exports symbols without the orr_/orrery_ prefix: $(echo $others | head -c 300)"
nm -D --defined-only "$so" | grep -q ' T orrery_open@' || fail "liborrery.so does not export orrery_open"
[ -f "$WORK/prefix/share/orrery/configs/first-light.yaml" ] || fail "configs not installed"

flags=""
grep -q "ORRERY_SANITIZE:BOOL=ON" "$build/CMakeCache.txt" && flags="-fsanitize=address,undefined"
export PKG_CONFIG_PATH="$libdir"
cc -std=c11 $flags "$SRC/examples/library/render_scene.c" $(pkg-config --cflags --libs orrery) \
  -o render_scene 2>cc.log || fail "building against the installed library: $(cat cc.log)"

printf 'x y z mass\n0 0 0 2\n0.5 0.5 0 3\n' >t.txt
write_scene s.yaml t.txt
LD_LIBRARY_PATH="$(dirname "$libdir")" ./render_scene s.yaml t.txt output.png=false >run.out 2>&1 ||
  fail "render_scene failed: $(cat run.out)"
grep -q "2 particles rendered" run.out || fail "render_scene output: $(cat run.out)"
# In-situ outputs carry the frame number; the FITS header counts the weight.
[ -f out/s_0000.fits ] || fail "render_scene wrote no FITS: $(ls out)"
grep -aEq "WIMAGE  = +(5\.|4\.99999)" out/s_0000.fits || fail "render_scene: the weight in the image is not 5"
[ -f out/s_0000.png ] && fail "output.png=false not honoured"

# OpenImageIO is a module loaded on first use (liborrery-oiio.so, installed
# beside the library): neither the library nor the CLI needs it to start,
# and the installed CLI finds it for a TIFF.
readelf -d "$so" "$WORK/prefix/bin/orrery" | grep -q "OpenImageIO" && fail "liborrery or the CLI links OpenImageIO"
[ -f "$(dirname "$libdir")/liborrery-oiio.so" ] || fail "liborrery-oiio.so not installed beside the library"
"$WORK/prefix/bin/orrery" render -q s.yaml --set output.image=tif -o tif >run.out 2>&1 || fail "installed CLI, TIFF: $(cat run.out)"
[ -f tif/s.tif ] || fail "the installed CLI wrote no TIFF: $(ls tif)"

finish
