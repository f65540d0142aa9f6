#!/usr/bin/env bash
# The shared part of the bench/*/run.sh scripts that time texbake alone
# (layers, photos, large_images): source it after scripts/setup.sh.
#
#   bench_options REPS WORK "$@"   parses -n N (repetitions, default REPS),
#                                  -w DIR (work folder, default WORK) and
#                                  -t vertex|atlas|all (default all) into
#                                  $reps, $work and $which; -h, or a bad
#                                  flag (exit 2), prints the calling
#                                  script's header comment
#   bench_start [PKG...]           builds build/texbake when missing,
#                                  installs `time` and PKG..., enters $work,
#                                  prints texbake's version and the machine
#   timed ARGS...                  runs texbake ARGS, prints "seconds peak_MB"
#   median REPORT ARGS...          $reps runs of texbake ARGS --report
#                                  REPORT.i.json: prints the median run's
#                                  "seconds peak_MB report"
#   bench_photograph MESH UP        24 views of MESH at 1920 x 1080 (the Earth
#                                  map from its fitted sphere, unlit) as the
#                                  COLMAP workspace NAME/ws, once

bench_options() {
  reps=$1
  work=$2
  which=all
  shift 2
  local opt OPTIND=1
  while getopts "n:w:t:h" opt; do
    case $opt in
    n) reps=$OPTARG ;;
    w) work=$OPTARG ;;
    t) which=$OPTARG ;;
    *)
      awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"
      [ "$opt" = h ] && exit 0
      exit 2
      ;;
    esac
  done
  case $which in vertex | atlas | all) ;; *)
    echo "run.sh: -t takes vertex, atlas or all, not '$which'" >&2
    exit 2
    ;;
  esac
  if ! [[ $reps =~ ^[1-9][0-9]*$ ]]; then
    echo "run.sh: -n takes a positive count, not '$reps'" >&2
    exit 2
  fi
}

bench_start() {
  texbake="$TEXBAKE_BUILD/texbake"
  [ -x "$texbake" ] || texbake_build texbake
  texbake_install_packages time "$@"
  py=/usr/bin/python3
  mkdir -p "$work"
  cd "$work"
  echo "texbake: $("$texbake" --version | head -1)"
  echo "machine: $(nproc) cores, $(free -g | awk '/^Mem/ {print $2 " GB"}'), $(uptime | sed 's/.*load average/load average/')"
}

timed() {
  local start end peak_kb ms
  start=$(date +%s%N)
  /usr/bin/time -v -o time.log "$texbake" "$@"
  end=$(date +%s%N)
  peak_kb=$(awk -F': ' '/Maximum resident set size/ {print $2}' time.log)
  ms=$(((end - start) / 1000000))
  printf '%d.%03d %d\n' $((ms / 1000)) $((ms % 1000)) $((peak_kb / 1024))
}

median() { # report args...
  local report=$1 i s p
  shift
  : >runs.tsv
  for ((i = 0; i < reps; i++)); do
    read -r s p < <(timed "$@" --report "$report.$i.json")
    echo "$s $p $report.$i.json" >>runs.tsv
  done
  sort -n runs.tsv | sed -n "$(((reps + 1) / 2))p"
}

bench_photograph() { # mesh up
  local name=${1%.*}
  if [ ! -f "$name/ws/sparse/0/images.txt" ]; then
    rm -rf "$name"
    mkdir -p "$name"
    "$texbake" fit "$1" --proxy sphere --up "$2" -o "$name/sphere.json" >/dev/null
    "$texbake" render "$1" --texture "$TEXBAKE_ROOT/data/earth.jpg" --proxy-file "$name/sphere.json" \
      --up "$2" --unlit --views 24 --samples 4 --size 1920x1080 --colmap "$name/ws" >/dev/null
  fi
}

# The photographs benchmarks' meshes in the work folder: the bunny and the
# armadillo subdivided to 832k triangles, each photographed 24 times.
bench_photo_meshes() {
  [ -f armadillo_832k.ply ] ||
    "$py" "$TEXBAKE_ROOT/bench/peers/peers_util.py" mesh "$TEXBAKE_ROOT/data/armadillo.off" \
      armadillo_832k.ply
  cp "$TEXBAKE_ROOT/data/bunny00.off" bunny.off
  bench_photograph bunny.off y
  bench_photograph armadillo_832k.ply y
}
