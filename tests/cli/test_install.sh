# cmake --install puts the library, the public header, CLI, pkg-config
# file and CMake package in place; a C and a C++ program built against them
# with pkg-config, and again with find_package(orrery), render a scene
# through the documented #include <orrery/orrery.h>; the shared library
# exports exactly the functions orrery.h declares; pkg-config --cflags gives
# only orrery's include folders.
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
# Exactly orrery.h's functions (and liborrery_mpi.a's hook, src/exports.map).
declared=$(grep -o '\borrery_[a-z_]*(' "$SRC/src/orrery.h" | tr -d '(' | sort -u)
exported=$(nm -D --defined-only "$so" | awk '$2 != "A" {sub(/@.*/, "", $3); print $3}' |
  grep -v '^orr_insitu_set_parallel$' | sort -u)
[ "$declared" = "$exported" ] ||
  fail "liborrery.so's exports are not orrery.h's functions: $(diff <(echo "$declared") <(echo "$exported") | head -c 400)"
nm -D --defined-only "$so" | grep -q ' T orrery_open@' || fail "liborrery.so does not export orrery_open"
[ -f "$WORK/prefix/share/orrery/configs/first-light.yaml" ] || fail "configs not installed"

flags=""
grep -q "ORRERY_SANITIZE:BOOL=ON" "$build/CMakeCache.txt" && flags="-fsanitize=address,undefined"
export PKG_CONFIG_PATH="$libdir"
for f in $(pkg-config --cflags orrery); do
  case "$f" in -I"$WORK"/prefix/*) ;; *) fail "pkg-config --cflags orrery gives $f, not orrery's include folder" ;; esac
done
cc -std=c11 $flags "$SRC/examples/library/render_scene.c" $(pkg-config --cflags --libs orrery) \
  -o render_scene 2>cc.log || fail "building against the installed library: $(cat cc.log)"
# The same API from C++ (extern "C" in orrery.h).
cat >render.cpp <<'CPP'
#include <orrery/orrery.h>
#include <cstdio>
int main(int argc, char **argv)
{
    orrery_renderer *r = nullptr;
    char msg[512];
    const char *sets[] = {"output.png=false"};
    if (argc < 2 || orrery_open(&r, argv[1], sets, 1, msg, sizeof msg) != ORRERY_OK)
        return std::puts(msg), 1;
    float x[2] = {0, 0.5f}, y[2] = {0, 0.5f}, z[2] = {0, 0}, m[2] = {2, 3};
    orr_particle_arrays p{};
    p.struct_size = sizeof p;
    p.n = 2;
    p.x = {x, ORR_F32, 0};
    p.y = {y, ORR_F32, 0};
    p.z = {z, ORR_F32, 0};
    p.mass = {m, ORR_F32, 0};
    int st = orrery_render(r, &p, 0);
    std::printf("%s: %d outputs\n", st ? orrery_error(r) : "rendered", orrery_output_count(r));
    orrery_close(r);
    return st;
}
CPP
c++ -std=c++17 $flags render.cpp $(pkg-config --cflags --libs orrery) -o render_cpp 2>cxx.log ||
  fail "building C++ against the installed library: $(cat cxx.log)"
# And with CMake's find_package(orrery).
mkdir -p cmake-user && cp "$SRC/examples/library/render_scene.c" render.cpp cmake-user/
cat >cmake-user/CMakeLists.txt <<'CMAKE'
cmake_minimum_required(VERSION 3.18)
project(orrery_user C CXX)
find_package(orrery 0.1 REQUIRED)
add_executable(render_c render_scene.c)
target_link_libraries(render_c PRIVATE orrery::orrery)
add_executable(render_cxx render.cpp)
target_link_libraries(render_cxx PRIVATE orrery::orrery)
CMAKE
{ cmake -S cmake-user -B cmake-user/build -DCMAKE_PREFIX_PATH="$WORK/prefix" -DCMAKE_C_FLAGS="$flags -std=c11" \
    -DCMAKE_CXX_FLAGS="$flags" && cmake --build cmake-user/build; } >cmake.log 2>&1 ||
  fail "find_package(orrery): $(tail -20 cmake.log)"

printf 'x y z mass\n0 0 0 2\n0.5 0.5 0 3\n' >t.txt
write_scene s.yaml t.txt
LD_LIBRARY_PATH="$(dirname "$libdir")" ./render_scene s.yaml t.txt output.png=false >run.out 2>&1 ||
  fail "render_scene failed: $(cat run.out)"
grep -q "2 particles rendered" run.out || fail "render_scene output: $(cat run.out)"
# In-situ outputs carry the frame number; the FITS header counts the weight.
[ -f out/s_0000.fits ] || fail "render_scene wrote no FITS: $(ls out)"
grep -aEq "WIMAGE  = +(5\.|4\.99999)" out/s_0000.fits || fail "render_scene: the weight in the image is not 5"
[ -f out/s_0000.png ] && fail "output.png=false not honoured"
rm -rf out
LD_LIBRARY_PATH="$(dirname "$libdir")" ./render_cpp s.yaml >cpp.out 2>&1 || fail "render_cpp failed: $(cat cpp.out)"
grep -q "rendered: 1 outputs" cpp.out || fail "render_cpp output: $(cat cpp.out)"
for program in render_c render_cxx; do
  rm -rf out
  if [ -x cmake-user/build/$program ]; then
    args="s.yaml"
    [ $program = render_c ] && args="s.yaml t.txt output.png=false"
    cmake-user/build/$program $args >cm.out 2>&1 || fail "$program (find_package) failed: $(cat cm.out)"
    [ -f out/s_0000.fits ] || fail "$program (find_package) wrote no FITS: $(cat cm.out)"
  fi
done

# OpenImageIO is a module loaded on first use (liborrery-oiio.so, installed
# beside the library): neither the library nor the CLI needs it to start,
# and the installed CLI finds it for a TIFF.
readelf -d "$so" "$WORK/prefix/bin/orrery" | grep -q "OpenImageIO" && fail "liborrery or the CLI links OpenImageIO"
[ -f "$(dirname "$libdir")/liborrery-oiio.so" ] || fail "liborrery-oiio.so not installed beside the library"
"$WORK/prefix/bin/orrery" render -q s.yaml --set output.image=tif -o tif >run.out 2>&1 || fail "installed CLI, TIFF: $(cat run.out)"
[ -f tif/s.tif ] || fail "the installed CLI wrote no TIFF: $(ls tif)"

finish
