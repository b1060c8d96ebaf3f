#!/usr/bin/env bash
# On a fresh Debian 12 machine: installs the dependencies, builds libbead,
# and runs the main jobs on the bundled sample run (testdata/sample):
# geometry, offset calibration, flow. Results go to out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)"
mkdir -p out
echo "== bead measure: cross-sections of the bundled sample run"
./build/tools/bead measure --rig testdata/sample/rig.yaml testdata/sample/run.h5 -o out/geometry.csv
echo "== first rows of out/geometry.csv"
head -n 4 out/geometry.csv
echo "== bead calibrate offset: the nozzle-to-laser offset from the sample's pin scans"
./build/tools/bead calibrate offset --rig testdata/sample/rig.yaml testdata/sample/pins.h5
echo "== bead flow: volumetric flow in extrusion time"
./build/tools/bead flow --rig testdata/sample/rig.yaml testdata/sample/run.h5 -o out/flow.csv
