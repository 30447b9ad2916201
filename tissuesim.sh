#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# TissueSim: set up, build and run on Debian 12.
#
#   ./tissuesim.sh run        install missing packages, build (Release), open the window on the
#                             bundled liver (headless run + snapshot PNG when there is no DISPLAY)
#   ./tissuesim.sh test       install missing packages, build (Release), run every test (ctest)
#   ./tissuesim.sh sanitize   the same tests in a separate ASan+UBSan build (build-asan/)
#   ./tissuesim.sh tsan       the physics loop's threaded tests under ThreadSanitizer (build-tsan/)
#   ./tissuesim.sh bench      the Google Benchmark suite (tissuesim bench)
#   ./tissuesim.sh measure [DIR]  every figure of docs/performance.md into DIR (build/measurements):
#                             the map (TRADE_ARGS=--quick: two minutes), the benchmarks
#                             (BENCH_FILTER=REGEX), the bundled poke's report, the liver poke
#                             against the continuum
#   ./tissuesim.sh fuzz       every parser under libFuzzer with ASan+UBSan (clang, build-fuzz/),
#                             FUZZ_SECONDS each (default 12), FUZZ_TARGETS to choose some
#
# Re-running is fast: packages are only installed when missing, and the build is incremental.
set -euo pipefail
cd "$(dirname "$0")"

PACKAGES=(
  cmake ninja-build g++ pkg-config
  libeigen3-dev nlohmann-json3-dev libcli11-dev libgtest-dev libbenchmark-dev
  libfcl-dev libccd-dev libassimp-dev libsuitesparse-dev libvtk9-qt-dev qtbase5-dev
  libopenblas0-pthread  # CHOLMOD's dense kernels, far faster than Debian's reference BLAS
  xvfb xauth libgl1-mesa-dri
  clang-format
)
JOBS=${JOBS:-2}
BUILD_ONLY=  # set for one build() call: that target alone

say() { printf '\033[1m==> %s\033[0m\n' "$*" >&2; }

install_packages() {
  local missing=()
  for package in "${PACKAGES[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
      missing+=("$package")
    fi
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  local sudo=()
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "tissuesim.sh: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
    sudo=(sudo)
  fi
  say "installing Debian packages: ${missing[*]}"
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -q
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"
}

# build DIR [CMAKE_ARGS...]: configure DIR once, then build everything in it; with
# BUILD_ONLY=name set, only that target and what it needs (`run` needs the program, not the tests).
build() {
  local dir=$1
  shift
  if [ ! -f "$dir/CMakeCache.txt" ]; then
    say "configuring $dir"
    cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@"
  fi
  say "building ${BUILD_ONLY:-everything} in $dir"
  cmake --build "$dir" -j "$JOBS" ${BUILD_ONLY:+--target "$BUILD_ONLY"}
}

# ctest runs JOBS tests at once, so each test's BLAS keeps to one thread: OpenBLAS's workers
# spinning beside another test slow both down.
blas_threads=${OPENBLAS_NUM_THREADS:-1}

run_tests() {
  local dir=$1
  say "testing $dir"
  OPENBLAS_NUM_THREADS=$blas_threads ctest --test-dir "$dir" --output-on-failure -j "$JOBS"
}

case "${1:-}" in
  run)
    install_packages
    BUILD_ONLY=tissuesim build build
    if [ -n "${DISPLAY:-}" ]; then
      say "opening the window on the bundled liver scene (move the mouse to steer the tool, wheel to push)"
      exec build/app/tissuesim
    fi
    # No display (a server, CI): the same scene headless, and a picture of it.
    say "no DISPLAY, so no window: a headless poke of the bundled liver scene instead"
    build/app/tissuesim run --scene assets/scenes/liver-poke.json --report build/liver-poke-report.json
    build/app/tissuesim snapshot --scene assets/scenes/liver-poke.json --frames 36 --colour-map \
      --output build/liver-poke.png
    say "report in build/liver-poke-report.json, image in build/liver-poke.png; with X, this opens the window"
    ;;
  test)
    install_packages
    build build
    run_tests build
    ;;
  sanitize)
    install_packages
    build build-asan -DTISSUESIM_SANITIZE=ON
    # Not the image and window tests: Mesa's llvmpipe and Qt's X plugin are not built with
    # ASan, leak by design at exit, and are slow under it. Nor the minute-long soak (its
    # five-second version runs here), nor the lint checks (the sources' layout, licences and
    # layering: nothing built runs in them). They run in `test`.
    # SANITIZE_SKIP_LONG=1 (CI) leaves out, too, the four tests that take minutes each under ASan
    # (docs/performance-details.md, "The build", has their times): probes held deep, quasi-Newton
    # against implicit Euler, the FEM's volume cells on a Gmsh mesh, the liver's recovery from
    # deep and fast pokes. They repeat, for many steps, paths that shorter tests take under ASan;
    # they run in `test`. And two that repeat on the 20,000-spring liver what runs here on the
    # smaller ones: the drawn surface's contact (its 1,000 and 5,300-spring cases stay) and the
    # bundled poke. And three long scene runs whose parts shorter tests take under ASan: the
    # smoothed strains' poke (a short poke per face and the force fields' own tests stay), the
    # Mullins set of a deep fast poke without weight, the cursor jump (the tool proxy's own tests
    # stay). And the FEM at its own rate's liver poke against the reference, its sideways sweep,
    # its deep press held in the softened liver and `run` on its scene and on that scene under
    # gravity (its shorter pokes through the same scene, softened, stay).
    long='Simulation\.(AProbeHeldSevenToNineCentimetresDeepComesToRest|QuasiNewtonPokesTheLiverAsImplicitEulerDoes|OnAGmshMeshTheFemLocksUnderAVolumePerTetAndNotUnderOnePerNode|TheLiverRecoversItsShapeAfterDeepAndFastPokes|OnTheTwentyThousandSpringLiverTheBundledPokeInvertsNoTet|TheFemWithSmoothedStrainPokesTheLiverSofterThanPerTetAndRecovers|WeightlessTheMullinsPermanentSetOfADeepFastPokeIsUnderHalfAMillimetre|ACursorJumpMovesTheToolAtBoundedSpeedAndTheForceStaysContinuous)$|HapticRateBody\.(TheBundledScenePokesTheLiverWithinTenPerCentOfTheReference|SteeringThePressedProbeSidewaysReportsNothing|HeldDeepInTheSoftenedLiverNothingIsReported)$|cli\.run_fem_haptic_rate(_heavy)?$|DrawnSurfaceContact\.TheTipMeetsTheDrawnLiverAndStaysOutOfItAt2N/liver20000'
    say "testing build-asan (all but the image, window and lint tests, the long soak${SANITIZE_SKIP_LONG:+ and fourteen long tests})"
    ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 OPENBLAS_NUM_THREADS=$blas_threads \
      ctest --test-dir build-asan --output-on-failure -j "$JOBS" -LE "image|gui|soak|lint" \
      ${SANITIZE_SKIP_LONG:+-E "$long"}
    ;;
  tsan)
    install_packages
    if [ ! -f build-tsan/CMakeCache.txt ]; then
      cmake -S . -B build-tsan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTISSUESIM_THREAD_SANITIZE=ON
    fi
    say "building build-tsan (the files of the threaded tests only)"
    cmake --build build-tsan -j "$JOBS" --target threaded_tests
    say "threaded tests under ThreadSanitizer"
    # CHOLMOD's OpenMP loops and OpenBLAS (in the FEM updates of HapticRateBody's test) on one
    # thread each: neither libgomp nor OpenBLAS is instrumented, and TSan reads their threads'
    # writes to the solver's workspace as races with the thread that started them.
    TSAN_OPTIONS=halt_on_error=1 OMP_THREAD_LIMIT=1 OPENBLAS_NUM_THREADS=1 build-tsan/tests/threaded_tests --gtest_filter='TripleBuffer.*:RealTimeLoop.*:ForkJoinPool.*:SpringForceField.ResultsDoNotDependOnTheThreadCount:BlockConjugateGradient.ResultsDoNotDependOnTheThreadCount:NodeBlockMatrix.ResultsDoNotDependOnTheThreadCount:SystemOperator.PartsAreIndependentOfOrderAndThreads:VolumeForceField.InspectionOnThePoolFindsWhatTheSerialOneDoes:VolumeForceField.PassesOnThePoolAreBitIdenticalToTheSerialOnes:NodalVolumeForceField.PassesOnThePoolAreBitIdenticalToTheSerialOnes:TetIsochoricForceField.OneThreadAndTwoGiveTheSameBits:*SmoothedStrain.PassesOnThePoolAreBitIdenticalToTheSerialOnes/*:SessionAssessment.OneThreadAndTwoGiveTheSameFigures:ParallelPasses.*:FemModel.TwoThreadsEvaluateWhatOneDoes:FemModel.ManyRightHandSidesSolvedOnTwoThreadsAreEachColumnsOwnSolve:HapticRateBody.AResetWithAnUpdateInFlightStartsAfresh:HapticRateBody.AGraspLiftsTheLiverAsTheStaticFemsAndLetsGo'
    ;;
  fuzz)
    PACKAGES+=(clang libclang-rt-14-dev)  # the compiler and its libFuzzer runtime
    install_packages
    if [ ! -f build-fuzz/CMakeCache.txt ]; then
      CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DTISSUESIM_FUZZ=ON
    fi
    say "building build-fuzz (core and the fuzz targets)"
    cmake --build build-fuzz -j "$JOBS"
    seconds=${FUZZ_SECONDS:-12}
    # A file that hangs a library in the isolated readers costs 2 s here, not the program's 60.
    export TISSUESIM_READER_SECONDS=2
    # JOBS targets at once, one core each, each into its own log: its final figures are shown
    # when it ends, its whole log when it finds something (and the stage then fails).
    mkdir -p build-fuzz/findings build-fuzz/logs
    fuzz_one() {
      local target=$1 log=build-fuzz/logs/$1.log
      mkdir -p "build-fuzz/corpus/$target"
      # New inputs go to build-fuzz/corpus; the seeds in tests/fuzz/corpus are only read.
      if "build-fuzz/tests/fuzz/fuzz_$target" -max_total_time="$seconds" -max_len=65536 \
        -print_final_stats=1 -artifact_prefix="build-fuzz/findings/$target-" \
        "build-fuzz/corpus/$target" "tests/fuzz/corpus/$target" >"$log" 2>&1; then
        say "fuzzed $target for $seconds s: $(grep -m1 -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$') runs"
      else
        cat "$log" >&2
        say "fuzzing $target failed (its log above; an input that fails is kept in build-fuzz/findings/)"
        return 1
      fi
    }
    failed=0
    running=0
    for target in ${FUZZ_TARGETS:-tissue_file scene_file instrument_script tet_mesh_gmsh tet_mesh_tetgen surface_file vtk_mesh fit_csv recording}; do
      if [ "$running" -ge "$JOBS" ]; then
        wait -n || failed=1
        running=$((running - 1))
      fi
      say "fuzzing $target for $seconds s"
      fuzz_one "$target" &
      running=$((running + 1))
    done
    while [ "$running" -gt 0 ]; do
      wait -n || failed=1
      running=$((running - 1))
    done
    [ "$failed" -eq 0 ]
    ;;
  bench)
    install_packages
    build build
    shift
    build/app/tissuesim bench "$@"
    ;;
  measure)
    # Every figure of docs/performance.md: the speed/accuracy map, the benchmarks, the
    # bundled poke's report and the liver poke against the continuum, into one folder.
    # TRADE_ARGS=--quick for the two-minute map.
    install_packages
    BUILD_ONLY=tissuesim build build
    out=${2:-build/measurements}
    mkdir -p "$out"
    # First: the liver poke's FEM reference is solved again (13 minutes) only when the one kept in
    # assets/meshes/liver-fem-poke.csv is not the bundled scene's, and the map reads it.
    say "the liver poke against the continuum into $out/organ-poke.csv"
    build/app/tissuesim organ-poke --springs 1000,5300,20000 \
      --fem-cache assets/meshes/liver-fem-poke.csv --output "$out/organ-poke.csv"
    # The same poke at a second site, 4 cm along the liver from the first, where the FEM at its
    # own rate's bundled body is coarse: the default scene, that scene and the one that refines its
    # body where the tool aims, against a reference graded there (kept to 5 mm in
    # assets/meshes/liver-fem-site-b-poke.csv).
    for scene in liver-poke liver-fem-haptic-rate liver-fem-refined; do
      say "the liver poke at the second site ($scene) into $out/organ-poke-site-b-$scene.csv"
      build/app/tissuesim organ-poke --scene "assets/scenes/$scene.json" \
        --probe-at -0.04,0.152,0.045 --depths-mm 1,2,3,4,5 \
        --fem-mesh assets/meshes/liver-fem-site-b.msh \
        --fem-cache assets/meshes/liver-fem-site-b-poke.csv \
        --output "$out/organ-poke-site-b-$scene.csv"
    done
    # The liver as the default scene holds it (its weight, the tray), settled first, in the
    # reference (kept to 5 mm in assets/meshes/liver-fem-weighted-poke.csv; 8 minutes to solve)
    # and in each scene given the default scene's gravity and tray.
    for scene in liver-poke liver-fem-haptic-rate liver-fem-refined; do
      say "the liver poke under gravity ($scene) into $out/organ-poke-weighted-$scene.csv"
      scene_file="assets/scenes/$scene.json"
      if [ "$scene" != liver-poke ]; then
        scene_file="$out/$scene-weighted.json"
        python3 - "assets/scenes/$scene.json" "$scene_file" <<'PY'
import json, os, sys
source, target = sys.argv[1], sys.argv[2]
scene = json.load(open(source))
bundled = json.load(open(os.path.join(os.path.dirname(source), "liver-poke.json")))
scene["gravity_m_s2"], scene["tray"] = bundled["gravity_m_s2"], bundled["tray"]
here = os.path.dirname(os.path.abspath(source))
scene["tissue"] = os.path.join(here, scene["tissue"])
scene["surface"]["file"] = os.path.join(here, scene["surface"]["file"])
scene["tet_mesh"]["file"] = os.path.join(here, scene["tet_mesh"]["file"])
json.dump(scene, open(target, "w"), indent=2)
PY
      fi
      build/app/tissuesim organ-poke --scene "$scene_file" --weighted --depths-mm 1,2,3,4,5 \
        --fem-cache assets/meshes/liver-fem-weighted-poke.csv \
        --output "$out/organ-poke-weighted-$scene.csv"
    done
    # The refined scene under gravity, its body refined to FINEST mm growing GROWTH mm per mm
    # and each update used 150 ms after it starts, into OUT (graded_scene FINEST GROWTH OUT).
    graded_scene() {
      python3 - "$out/liver-fem-refined-weighted.json" "$3" "$1" "$2" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scene["tet_mesh"]["refine_towards_tool"].update(finest_mm=float(sys.argv[3]), growth=float(sys.argv[4]))
scene["physics"]["fem_update_latency_ms"] = 150
json.dump(scene, open(sys.argv[2], "w"), indent=2)
PY
    }
    # The body refined to 2 mm growing 1 (docs/performance-details.md, "Under gravity within
    # 10 % at every depth, given the update's time") at 2, 3 and 3.2 mm/s; each run's node count
    # and mean update in the .txt beside its forces.
    graded_scene 2 1 "$out/liver-fem-refined-weighted-2mm.json"
    for speed in 2 3 3.2; do
      say "the liver poke under gravity (the 2 mm body, updates used 150 ms after they start) at $speed mm/s"
      build/app/tissuesim organ-poke --scene "$out/liver-fem-refined-weighted-2mm.json" --weighted \
        --depths-mm 1,2,3,4,5 --speed-mm-s "$speed" \
        --fem-cache assets/meshes/liver-fem-weighted-poke.csv \
        --output "$out/organ-poke-weighted-2mm-150ms-$speed.csv" \
        2> "$out/organ-poke-weighted-2mm-150ms-$speed.txt"
      cat "$out/organ-poke-weighted-2mm-150ms-$speed.txt" >&2
    done
    # Every other body the refinement makes of that mesh, at 2 mm/s (the table closing the same
    # section; the 2 mm / 1 row is the run at 2 mm/s above).
    for grading in 2,3 4,2 4,1 2.5,2 3,1 2.5,1; do
      finest=${grading%,*} growth=${grading#*,}
      say "the liver poke under gravity on the body refined to $finest mm growing $growth"
      graded_scene "$finest" "$growth" "$out/liver-fem-refined-weighted-grading.json"
      build/app/tissuesim organ-poke --scene "$out/liver-fem-refined-weighted-grading.json" --weighted \
        --depths-mm 1,2,3,4,5 --fem-cache assets/meshes/liver-fem-weighted-poke.csv \
        --output "$out/organ-poke-weighted-grading-$finest-$growth.csv" \
        2> "$out/organ-poke-weighted-grading-$finest-$growth.txt"
      cat "$out/organ-poke-weighted-grading-$finest-$growth.txt" >&2
    done
    # The block of the map's error column through the FEM at its own rate, as the bundled FEM
    # scenes run it (one Newton iteration an update at a tenth of the reference's bulk
    # modulus, each update used 60 ms after it starts), against the refinement-3 reference.
    say "the block at the haptic rate into $out/indent-haptic-rate.csv"
    build/app/tissuesim indent --tissue assets/tissues/porcine-liver.json --depths-mm 1,2,3,4 \
      --refinement 3 --models fem-haptic-rate --haptic-rate-iterations 1 \
      --haptic-rate-volume-term-kpa 26000 --update-latency-ms 60 \
      --output "$out/indent-haptic-rate.csv"
    say "the speed/accuracy map into $out"
    build/app/tissuesim trade ${TRADE_ARGS:-} --output "$out"
    # The quadratic rows' forces the map had to solve (their meshes' kept ones were stale or
    # missing) are kept beside their meshes for the next map.
    for kept in "$out"/liver-graded-*-poke.csv; do
      if [ -e "$kept" ]; then cp "$kept" assets/meshes/; fi
    done
    say "the benchmarks into $out/bench.json ${BENCH_FILTER:+(filter $BENCH_FILTER)}"
    build/app/tissuesim bench --benchmark_out="$out/bench.json" --benchmark_out_format=json \
      ${BENCH_FILTER:+--benchmark_filter=$BENCH_FILTER}
    say "the bundled poke into $out/liver-poke-report.json"
    build/app/tissuesim run --scene assets/scenes/liver-poke.json --report "$out/liver-poke-report.json"
    say "measurements in $out (the machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs))"
    ;;
  *)
    echo "usage: ./tissuesim.sh run|test|sanitize|tsan|fuzz|bench|measure" >&2
    exit 2
    ;;
esac
