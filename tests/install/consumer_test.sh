#!/usr/bin/env bash
# An outside project against the installed package: cmake --install into a
# fresh prefix, then a consumer configured with find_package(bead), a C
# program built with pkg-config, each run; the hot-path consumer must not
# need HDF5, Ceres or OpenCV at run time.
#   consumer_test.sh BUILD_DIR SOURCE_DIR WORK_DIR
set -euo pipefail
build=$1 src=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
prefix=$work/prefix
cmake --install "$build" --prefix "$prefix" >/dev/null
# The public headers, not the internals (cmake/install.cmake).
for h in profile/profile_processor.h model/model_file.h io/contained.h; do
  [ -f "$prefix/include/libbead/$h" ] || { echo "public header $h not installed" >&2; exit 1; }
done
for h in profile/vec8.h profile/kernel.h part/part_kernel.h part/grid_costs.h profile/bead_heights.h sim/sim_yaml_reader.h sim/sim_timeline.h model/output_error.h vision/stripe_line.h; do
  [ ! -e "$prefix/include/libbead/$h" ] || { echo "internal header $h installed" >&2; exit 1; }
done
cmake -S "$src/tests/install/consumer" -B "$work/consumer" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_RPATH="$prefix/lib" >/dev/null
cmake --build "$work/consumer" >/dev/null
"$work/consumer/core_consumer"
"$work/consumer/c_consumer"
"$work/consumer/io_consumer" "$src/testdata/sample/rig.yaml"
# A CXX-only project and a C-only one find the package without the full
# components' packages (HDF5's find module needs C; none is looked up).
for kind in cxx c; do
  cmake -S "$src/tests/install/consumer_$kind" -B "$work/consumer_$kind" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_RPATH="$prefix/lib" >"$work/consumer_$kind.log" 2>&1 ||
    { cat "$work/consumer_$kind.log" >&2; echo "the $kind-only consumer does not configure" >&2; exit 1; }
  if grep -qi 'hdf5\|ceres\|opencv' "$work/consumer_$kind/CMakeCache.txt"; then
    echo "the $kind-only consumer looked up the full components' packages" >&2
    exit 1
  fi
  cmake --build "$work/consumer_$kind" >/dev/null
done
"$work/consumer_cxx/core_consumer"
"$work/consumer_c/c_consumer"
if readelf -d "$work/consumer_cxx/core_consumer" | grep -Ei 'NEEDED.*(hdf5|ceres|opencv|yaml|glog)'; then
  echo "core_consumer links what bead::core must not need" >&2
  exit 1
fi
# The C interface by pkg-config alone.
export PKG_CONFIG_PATH=$prefix/lib/pkgconfig
cc -std=c11 "$src/tests/install/consumer/c_consumer.c" $(pkg-config --cflags --libs bead) -lm \
  -Wl,-rpath,"$prefix/lib" -o "$work/c_pkgconfig"
"$work/c_pkgconfig"
# The installed tool finds its occlusion module (LIBDIR/bead) when a fit runs.
"$prefix/bin/bead" measure --rig "$src/testdata/sample/rig.yaml" "$src/testdata/sample/run.h5" \
  -o "$work/geometry.csv" | grep -q "occlusion (pooled"
# What --help points at is installed: the documents, the example configs,
# the sample (found by the installed tool itself), a man page per command
# made from its --help, and bash completion read from --help.
for f in share/doc/bead/data-formats.md share/doc/bead/README.md share/bead/testdata/configs/sample.yaml \
  share/bead/testdata/step/heater_step.csv share/man/man1/bead.1 share/man/man1/bead-measure.1 \
  share/man/man1/bead-calibrate.1 share/bash-completion/completions/bead; do
  [ -s "$prefix/$f" ] || { echo "$f not installed" >&2; exit 1; }
done
grep -q '^\.TH BEAD-MEASURE 1' "$prefix/share/man/man1/bead-measure.1"
grep -q -- '--rig' "$prefix/share/man/man1/bead-measure.1"
grep -q -- '--board' "$prefix/share/man/man1/bead-calibrate.1"  # calibrate laser's help in calibrate's page
mkdir -p "$work/empty"
(cd "$work/empty" && "$prefix/bin/bead" flow) | grep -q "bundled sample run $prefix/share/bead/testdata/sample/run.h5"
source "$prefix/share/bash-completion/completions/bead"
COMP_WORDS=("$prefix/bin/bead" me) COMP_CWORD=1 && _bead
[ "${COMPREPLY[*]}" = measure ] || { echo "completion of 'bead me': '${COMPREPLY[*]}'" >&2; exit 1; }
COMP_WORDS=("$prefix/bin/bead" measure --ri) COMP_CWORD=2 && _bead
[ "${COMPREPLY[*]}" = --rig ] || { echo "completion of 'bead measure --ri': '${COMPREPLY[*]}'" >&2; exit 1; }
COMP_WORDS=("$prefix/bin/bead" calibrate w) COMP_CWORD=2 && _bead
[ "${COMPREPLY[*]}" = wheel ] || { echo "completion of 'bead calibrate w': '${COMPREPLY[*]}'" >&2; exit 1; }
# The build tree's bead.pc (PKG_CONFIG_PATH=BUILD) builds the C interface's user.
PKG_CONFIG_PATH=$build cc -std=c11 "$src/tests/install/consumer/c_consumer.c" $(PKG_CONFIG_PATH=$build pkg-config \
  --cflags --libs bead) -lm -o "$work/c_build_tree"
"$work/c_build_tree"
echo "consumer: all ran"
