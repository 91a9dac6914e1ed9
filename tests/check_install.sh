#!/usr/bin/env bash
# The installed package as a host uses it (docs/EMBEDDING.md). Installs BUILD_DIR into a scratch
# prefix; checks that the public header compiles alone, with no flag of the library, reaching no
# torch, Eigen or JSON header, and that the library exports none of their symbols; trains a tiny
# model with the installed nsf; builds examples/embed against the prefix with the host's default
# flags and with -march=native; runs each with the collider raised by the host and held still.
# A C++14 host gets C++17 from the imported target; pkg-config builds the C host; the man page
# and the bash completion are installed and work. The loader takes the runtime's x86-64-v3 copy on
# a CPU that has it, and the baseline copy runs the C host too. Then the C API (include/nsf/nsf.h):
# the header alone as C99 (-pedantic -Werror) and as C++, examples/c built against the prefix and
# run, and examples/rust (cargo build --offline, no crates) run, printing what the C host printed
# (skipped, saying so, where cargo is absent). An MLP model runs in the C host through the installed
# MLP plugin (LIBDIR/nsf/libnsf_mlp.so), which the runtime does not link, and without the plugin
# the host gets NSF_ERROR_SETUP naming where it looked.
# Usage: tests/check_install.sh BUILD_DIR SOURCE_DIR. Run by ctest (install_and_embed).
set -euo pipefail
build=$(cd "$1" && pwd)
src=$(cd "$2" && pwd)
tmp=$(mktemp -d "${TMPDIR:-/tmp}/nsf_install.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
die() {
  echo "check_install: $*" >&2
  exit 1
}
step() { echo "== $* ($SECONDS s)"; }

prefix="$tmp/prefix"
step "install into $prefix"
cmake --install "$build" --prefix "$prefix" >/dev/null
lib=$(ls "$prefix"/lib*/libnsf_runtime.so) || die "no libnsf_runtime.so installed"
[[ -x "$prefix/bin/nsf" ]] || die "no bin/nsf installed"
extra=$(cd "$prefix/include" && find . -type f ! -path './nsf/*')
[[ -z "$extra" ]] || die "headers installed outside include/nsf: $extra"

step "the public header alone"
echo '#include <nsf/runtime.h>' >"$tmp/header_only.cpp"
c++ -std=c++17 -fsyntax-only -H -I "$prefix/include" "$tmp/header_only.cpp" 2>"$tmp/included.txt"
# Past nsf's own headers, whose random temporary path could spell "c10" too.
if grep -vF "$prefix/include/nsf/" "$tmp/included.txt" | grep -Ei 'torch|c10|eigen|nlohmann|/src/'; then
  die "the public header reaches the headers above"
fi
if nm -DC --defined-only "$lib" | grep -E ' (Eigen|at|c10|torch|nlohmann)::'; then
  die "libnsf_runtime.so exports the symbols above"
fi
for lang in "c -std=c99" "c++ -std=c++17"; do
  echo '#include <nsf/nsf.h>' | cc -x $lang -Wall -Wextra -pedantic -Werror -fsyntax-only \
    -I "$prefix/include" - || die "nsf/nsf.h does not compile alone as ${lang#* }"
done
for fn in nsf_version nsf_last_error nsf_runtime_create nsf_runtime_destroy nsf_runtime_stress nsf_runtime_affine \
  nsf_runtime_object_pose; do
  nm -D --defined-only "$lib" | grep -q " T $fn\$" || die "libnsf_runtime.so does not export $fn"
done

step "a tiny model, trained by the installed nsf"
scene="$src/scenes/examples/rom_tiny.json"
"$prefix/bin/nsf" sweep "$scene" --out "$tmp/data" --jobs 2 -j 1 -q >/dev/null
"$prefix/bin/nsf" train "$tmp/data" --out "$tmp/tiny.nsf" -r 2 --depth 2 --widths 32,16,16 \
  --encoder-hidden 8 --steps 100,50,50 --refine-latents 0 -j 2 -q \
  --frames-per-batch 2 --particles-per-frame 64 >/dev/null

for flags in "" "-march=native"; do
  name=host${flags:+_native}
  step "examples/embed against the prefix, CXXFLAGS='$flags'"
  cmake -S "$src/examples/embed" -B "$tmp/$name" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_CXX_FLAGS="$flags" >/dev/null
  cmake --build "$tmp/$name" >/dev/null
  "$tmp/$name/embed" "$tmp/tiny.nsf" "$scene" 1.0 0.5 >"$tmp/$name.moved" ||
    die "$name: the example failed (raised collider)"
  "$tmp/$name/embed" "$tmp/tiny.nsf" "$scene" 1.0 0 >"$tmp/$name.still" ||
    die "$name: the example failed (still collider)"
done
cat "$tmp/host.moved"

step "what the runs printed"
frames=$(grep -c '^frame' "$tmp/host.moved")
((frames == 12)) || die "the example printed $frames frames, the scene has 12"
grep -q '^frame 12 .* x0 [-0-9.]\+ [-0-9.]\+ [-0-9.]\+$' "$tmp/host.moved" || die "no positions"
# The collider's pose, echoed back: raised by 0.5 m/s over 12 frames of 15 ms.
y_moved=$(awk '/^frame 12/ {print $7}' "$tmp/host.moved")
y_still=$(awk '/^frame 12/ {print $7}' "$tmp/host.still")
awk -v a="$y_moved" -v b="$y_still" 'BEGIN { exit !(a - b > 0.089 && a - b < 0.091) }' ||
  die "the collider is at y $y_moved raised, $y_still still: not 0.09 m apart"
# The material feels it.
cmp -s <(awk '/^frame/ {print $10, $13}' "$tmp/host.moved") \
  <(awk '/^frame/ {print $10, $13}' "$tmp/host.still") &&
  die "moving the collider changed no position"
# The bar's pose: its centre of mass is its particles' mean (one material, equal masses).
grep -q '^object 0  centre [-0-9.]\+ [-0-9.]\+ [-0-9.]\+  turned [0-9.]\+ rad  misfit [0-9.]\+ m$' \
  "$tmp/host.moved" || die "no object pose"
c_y=$(awk '/^object 0/ {print $5}' "$tmp/host.moved")
m_y=$(awk '/^frame 12/ {print $10}' "$tmp/host.moved")
awk -v a="$c_y" -v b="$m_y" 'BEGIN { d = a - b; exit !(d < 2e-5 && d > -2e-5) }' ||
  die "the bar's centre of mass is at y $c_y, its particles' mean at $m_y"
# The host's flags change nothing.
cmp "$tmp/host.moved" "$tmp/host_native.moved" || die "-march=native host printed otherwise"
cmp "$tmp/host.still" "$tmp/host_native.still" || die "-march=native host printed otherwise"

step "examples/c against the prefix (C99, -Wall -Wextra -pedantic -Werror)"
cmake -S "$src/examples/c" -B "$tmp/c_host" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_C_FLAGS="-Wall -Wextra -pedantic -Werror" >/dev/null
cmake --build "$tmp/c_host" >/dev/null
"$tmp/c_host/c_host" "$tmp/tiny.nsf" "$scene" 1.0 0.5 >"$tmp/c.out" || die "the C host failed"
cat "$tmp/c.out"
frames=$(grep -c '^frame' "$tmp/c.out")
((frames == 12)) || die "the C host printed $frames frames, the scene has 12"
grep -q '^missing model: NSF_ERROR_FILE_NOT_FOUND, nsf_runtime_create: .*does not exist$' \
  "$tmp/c.out" || die "the C host's missing model gave no code and message"
grep -q '^short buffer: NSF_ERROR_BUFFER_TOO_SMALL, ' "$tmp/c.out" || die "no short buffer error"
grep -q '^object 0: centre [-0-9.]\+ [-0-9.]\+ [-0-9.]\+  velocity .*  misfit [0-9.]\+ m$' \
  "$tmp/c.out" || die "the C host printed no object pose"
# The floor raised by the host lifts the bar: its centroid ends higher than with the floor still.
"$tmp/c_host/c_host" "$tmp/tiny.nsf" "$scene" 1.0 0 >"$tmp/c.still" || die "the C host failed"
y_moved=$(awk '/^frame 12 / {print $7}' "$tmp/c.out")
y_still=$(awk '/^frame 12 / {print $7}' "$tmp/c.still")
awk -v a="$y_moved" -v b="$y_still" 'BEGIN { exit !(a > b) }' ||
  die "the centroid is at y $y_moved with the floor raised, $y_still with it still"

step "an MLP model through the installed runtime and its MLP plugin"
plugin="$(dirname "$lib")/nsf/libnsf_mlp.so"
[[ -f "$plugin" ]] || die "no MLP plugin installed at $plugin"
# Library names only: a load address such as 0x00007fc8726c1000 holds "c10" too.
if ldd "$lib" | grep -E '(^|[[:space:]/])lib(torch|c10)[^[:space:]]*\.so'; then
  die "the installed runtime loads LibTorch (above): only its MLP plugin may"
fi
nm -D --defined-only "$plugin" | grep -q ' T nsf_mlp_plugin_table$' ||
  die "the MLP plugin does not export nsf_mlp_plugin_table"
if nm -D --defined-only "$plugin" | grep -v " nsf_mlp_plugin_table$"; then
  die "the MLP plugin exports more than its table (above)"
fi
"$prefix/bin/nsf" train "$tmp/data" --out "$tmp/tiny_mlp.nsf" --decoder mlp -r 2 --depth 2 \
  --widths 32,16,16 --encoder-hidden 8 --steps 100,50,50 --refine-latents 0 -j 2 -q \
  --frames-per-batch 2 --particles-per-frame 64 >/dev/null
env -u NSF_MLP_PLUGIN "$tmp/c_host/c_host" "$tmp/tiny_mlp.nsf" "$scene" 1.0 0.5 >"$tmp/c_mlp.out" ||
  die "the C host failed on an MLP model"
frames=$(grep -c '^frame' "$tmp/c_mlp.out")
((frames == 12)) || die "the C host printed $frames frames of the MLP model, the scene has 12"
awk '/^frame/ { for (i = 2; i <= NF; ++i) if ($i ~ /nan|inf/) exit 1 }' "$tmp/c_mlp.out" ||
  die "the C host printed a position that is not finite for the MLP model"
# The runtime's baseline copy runs it through the same plugin, ending where the other copy does.
if [[ -f "$(dirname "$lib")/glibc-hwcaps/x86-64-v3/libnsf_runtime.so.0" ]]; then
  env -u NSF_MLP_PLUGIN /lib64/ld-linux-x86-64.so.2 --glibc-hwcaps-mask x86-64-v2 \
    "$tmp/c_host/c_host" "$tmp/tiny_mlp.nsf" "$scene" 1.0 0.5 >"$tmp/c_mlp_base.out" ||
    die "the C host failed on an MLP model with the runtime's baseline copy"
  a=$(awk '/^frame 12 / {print $7}' "$tmp/c_mlp.out")
  b=$(awk '/^frame 12 / {print $7}' "$tmp/c_mlp_base.out")
  awk -v a="$a" -v b="$b" 'BEGIN { d = a - b; exit !(d < 1e-4 && d > -1e-4) }' ||
    die "the MLP model's centroid ends at y $b on the baseline copy, $a on the other"
fi
# The plugin moved away: nowhere to be found, the host gets a setup error that says what to do.
mv "$plugin" "$plugin.away"
status=0
env -u NSF_MLP_PLUGIN "$tmp/c_host/c_host" "$tmp/tiny_mlp.nsf" "$scene" 1.0 0.5 \
  >/dev/null 2>"$tmp/c_mlp.err" || status=$?
mv "$plugin.away" "$plugin"
((status != 0)) || die "the C host ran an MLP model without the plugin"
grep -q 'NSF_ERROR_SETUP' "$tmp/c_mlp.err" || die "no NSF_ERROR_SETUP without the plugin"
grep -qF "$plugin" "$tmp/c_mlp.err" || die "the error does not name $plugin"
echo "without the plugin: $(head -c 300 "$tmp/c_mlp.err")..."

step "the runtime's copy for x86-64-v3 CPUs (glibc-hwcaps), and the baseline copy"
libdir=$(dirname "$lib")
loader=/lib64/ld-linux-x86-64.so.2
if [[ -f "$libdir/glibc-hwcaps/x86-64-v3/libnsf_runtime.so.0" ]]; then
  printf '#include <nsf/nsf.h>\n#include <stdio.h>\nint main(void) { puts(nsf_build_arch()); return 0; }\n' \
    >"$tmp/arch.c"
  cc -std=c99 "$tmp/arch.c" -I "$prefix/include" -L "$libdir" -lnsf_runtime -Wl,-rpath,"$libdir" \
    -o "$tmp/arch"
  want=x86-64-v2
  "$loader" --help | grep -q "x86-64-v3 (supported, searched)" && want=x86-64-v3
  got=$("$tmp/arch")
  [[ "$got" == "$want" ]] || die "the loader took the runtime built for $got on a CPU for $want"
  # The loader told to skip the glibc-hwcaps folders takes the baseline copy, which runs the host.
  got=$("$loader" --glibc-hwcaps-mask x86-64-v2 "$tmp/arch")
  [[ "$got" == x86-64-v2 ]] || die "the baseline copy says it is built for $got"
  "$loader" --glibc-hwcaps-mask x86-64-v2 "$tmp/c_host/c_host" "$tmp/tiny.nsf" "$scene" 1.0 0.5 \
    >"$tmp/c_base.out" || die "the C host failed on the baseline copy"
  # The same lines, but for the figures in which the copies' rounding differs (FMA).
  figures='^frame\|^tau\|^object'
  cmp <(grep -v "$figures" "$tmp/c.out") <(grep -v "$figures" "$tmp/c_base.out") ||
    die "the C host printed otherwise on the baseline copy"
  frames=$(grep -c '^frame' "$tmp/c_base.out")
  ((frames == 12)) || die "the C host printed $frames frames on the baseline copy, the scene has 12"
  y_base=$(awk '/^frame 12 / {print $7}' "$tmp/c_base.out")
  awk -v a="$y_moved" -v b="$y_base" 'BEGIN { d = a - b; exit !(d < 1e-4 && d > -1e-4) }' ||
    die "the centroid ends at y $y_base on the baseline copy, $y_moved on the other"
  echo "the loader takes the copy for $want here; the baseline copy runs the C host too"
else
  echo "check_install: no glibc-hwcaps copy of the runtime (NSF_HWCAPS=OFF)"
fi

step "a C++14 host through find_package (the imported target asks for C++17) and pkg-config"
mkdir -p "$tmp/cxx14"
printf 'cmake_minimum_required(VERSION 3.20)\nproject(h LANGUAGES CXX)\nset(CMAKE_CXX_STANDARD 14)\nfind_package(nsf REQUIRED)\nmessage(STATUS "plugin: ${nsf_MLP_PLUGIN}")\nadd_executable(h main.cpp)\ntarget_link_libraries(h PRIVATE nsf::runtime)\n' \
  >"$tmp/cxx14/CMakeLists.txt"
cp "$src/examples/embed/main.cpp" "$tmp/cxx14/main.cpp"
cmake -S "$tmp/cxx14" -B "$tmp/cxx14/build" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" >"$tmp/cxx14.log"
# The package says where the MLP plugin is.
grep -qF -- "-- plugin: $(cd "$(dirname "$plugin")" && pwd -P)/libnsf_mlp.so" "$tmp/cxx14.log" ||
  grep -qF -- "-- plugin: $plugin" "$tmp/cxx14.log" ||
  die "the package's nsf_MLP_PLUGIN is not $plugin: $(grep -- '-- plugin' "$tmp/cxx14.log")"
cmake --build "$tmp/cxx14/build" >/dev/null || die "a C++14 host does not build against nsf::runtime"
pc="$(dirname "$lib")/pkgconfig"
[[ -f "$pc/nsf.pc" ]] || die "no nsf.pc installed"
PKG_CONFIG_PATH="$pc" pkg-config --modversion nsf | grep -qx "$("$prefix/bin/nsf" --version | awk 'NR==1 {print $2}')" ||
  die "pkg-config's nsf version is not nsf --version's"
# shellcheck disable=SC2046
cc -std=c99 -Wall -Wextra -Werror "$src/examples/c/main.c" -o "$tmp/c_pkg" \
  $(PKG_CONFIG_PATH="$pc" pkg-config --cflags --libs nsf) || die "the C host does not build with pkg-config"
"$tmp/c_pkg" "$tmp/tiny.nsf" "$scene" 1.0 0.5 | cmp - "$tmp/c.out" || die "the pkg-config host printed otherwise"

step "the manual page and the bash completion"
man1=$(ls "$prefix"/share/man/man1/nsf.1) || die "no man page installed"
grep -q '^\.TH NSF 1' "$man1" && grep -q '^\.SS generalize' "$man1" || die "the man page lacks its header or a command"
if command -v groff >/dev/null; then
  groff -man -Tutf8 -ww -z "$man1" 2>&1 | grep . && die "groff warns about the man page"
fi
comp="$prefix/share/bash-completion/completions/nsf"
[[ -f "$comp" ]] || die "no bash completion installed"
# shellcheck disable=SC1090
got=$(bash -c "source '$comp'; COMP_WORDS=(nsf gen); COMP_CWORD=1; _nsf; echo \"\${COMPREPLY[*]}\"")
[[ "$got" == "generalize" ]] || die "completing 'nsf gen' gave '$got'"
got=$(bash -c "source '$comp'; COMP_WORDS=(nsf sweep --ou); COMP_CWORD=2; _nsf; echo \"\${COMPREPLY[*]}\"")
[[ "$got" == "--out" ]] || die "completing 'nsf sweep --ou' gave '$got'"

if command -v cargo >/dev/null; then
  step "examples/rust against the prefix (cargo build --offline)"
  NSF_PREFIX="$prefix" CARGO_TARGET_DIR="$tmp/rust" cargo build --offline --locked --release -q \
    --manifest-path "$src/examples/rust/Cargo.toml" || die "examples/rust does not build"
  "$tmp/rust/release/rust_host" "$tmp/tiny.nsf" "$scene" 1.0 0.5 >"$tmp/rust.out" ||
    die "the Rust host failed"
  cmp "$tmp/c.out" "$tmp/rust.out" || die "the Rust host printed otherwise than the C host"
else
  echo "check_install: SKIPPED examples/rust: no cargo on PATH (the C API's Rust example is not checked)"
fi
step "check_install: the installed package builds and runs a host, with either flags, in C and Rust"
