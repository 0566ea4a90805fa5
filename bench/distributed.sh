#!/bin/sh
# Distributed runs under mpirun on this machine (issue "Beyond one machine"): the master
# and its workers are processes of one Open MPI job on loopback (shared memory), links
# emulated by the master's transport (--link, always labelled emulated).
#
# Usage: bench/distributed.sh BUILD_DIR [OUT_DIR]   (results in docs/benchmarks.md)
#        PARTS=BC bench/distributed.sh BUILD_DIR [OUT_DIR]   (only parts B and C)
#        LINKS, STRATEGIES, WORKERS, TABLE8_WORKERS, TABLE8_STRATEGIES: subsets of B and C
#        (TABLE8_STRATEGIES: static dynamic deep by default); REPEATS (1): each
#        cell of B, C and D run that many times (a fresh mpirun each), every run printed
#
#  A. Loopback goal: master + 2 workers of one pinned thread each, 1024x1024, 1 spp,
#     3 bounces, 12-frame orbit; `multiray bench` times each worker alone (through the
#     master, as a one-device run) and reports efficiency = ideal / actual frame time.
#  B. Seo et al. 2022, Table 9: S = 1, 2, 4, 8, 16 workers, each one thread at emulated
#     speed 0.1 (16 of them need 1.6 cores: they fit the machine), 512x512, 1 spp; static
#     (round-robin 64-px tiles, results once per frame), dynamic in the paper's form
#     (64-px tile queue, one tile index per worker, the next sent on its ready report:
#     `queue:tile=64`, the default pipeline=paper), dynamic in our deep pipeline (depth 2,
#     and --depth auto: `queue:tile=64:pipeline=deep`), hybrid (ours); efficiency =
#     tau_1 / (S tau_S), tau = mean frame time of frames 1..3 (frame 0 is left out: the
#     balancers start blind), on the mobile Wi-Fi and LAN presets.
#  C. Seo et al., Table 8: 1024x1024, 1 and 16 workers as in B, tile sizes 32..256, static
#     vs dynamic (the paper's form, and ours at depth 2), Wi-Fi.
#  D. Harada's hierarchy: 3 "machines" (ranks) of 2, 1 and 1 emulated devices (speeds 0.2 +
#     0.1, 0.15, 0.075), 256x256, fixed camera; the master splits the frame into row bands
#     (semi-static's split=rows on the master), each rank cuts its band into columns; Harada's balancer (semi-static) and ours
#     (hybrid) at either level; mean Harada deviation over the 4 devices (each timed on its
#     rank) and over the 3 ranks (timed by the master), frames 5..19.
set -eu
build=${1:?usage: bench/distributed.sh BUILD_DIR [OUT_DIR]}
out=${2:-/tmp/multiray_distributed}
bin="$build/src/app/multiray"
mpirun="mpirun --oversubscribe --allow-run-as-root"
parts=${PARTS:-ABCDE}
# Subsets for B and C (defaults: everything) and repeats of every cell of B, C and D (each
# repeat a fresh mpirun; the cells print every repeat's figure, to give a range).
links=${LINKS:-wifi lan}
strategies=${STRATEGIES:-static dynamic deep deep-auto hybrid}
workers=${WORKERS:-1 2 4 8 16}
table8_workers=${TABLE8_WORKERS:-1 16}
repeats=${REPEATS:-1}
mkdir -p "$out"

part() { case $parts in *$1*) return 0 ;; esac; return 1; }

# mean FIELD FIRST LAST < stats.json: mean of the FIELD lines of frames FIRST..LAST
mean() {
  grep "\"$1\":" | awk -v a="$2" -v b="$3" '{ gsub(/[",]/, "", $2); if (NR - 1 >= a && NR - 1 <= b) { s += $2; n++ } } END { printf "%.3f", s / n }'
}

if part A; then
echo "== A. loopback: master + 2 workers (1 pinned thread each), 1024x1024"
$mpirun -np 3 "$bin" bench --distributed --res 1024x1024 --spp 1 --bounces 3 --frames 12 \
  --warmup 4 --ideal-frames 3 --camera-path orbit:40 \
  --rank-devices 1=cpu:threads=1:cores=0 --rank-devices 2=cpu:threads=1:cores=1 \
  --balancers semi-static,hybrid,queue,queue:pipeline=deep,ospray-static --json "$out/loopback.json" \
  | tee "$out/loopback.txt"
fi

seo_run() {  # seo_run WORKERS LINK BALANCER EXTRA... -> mean frame ms of frames 1..3
  workers=$1 link=$2 balancer=$3
  shift 3
  dir="$out/seo_run"
  $mpirun -np $((workers + 1)) "$bin" render --distributed --res "${res:-512x512}" --spp 1 \
    --bounces 3 --frames 4 --camera-path orbit:40 --devices cpu:threads=1:speed=0.1 \
    --link "$link" --balancer "$balancer" "$@" -q --out "$dir" --overwrite 2> /dev/null
  mean frame_ms 1 3 < "$dir/stats.json"
}

# Seo's strategies by name: BALANCER and the remote options for `seo_run`.
seo_strategy() {  # seo_strategy NAME TILE -> sets b and extra
  case $1 in
    static) b=ospray-static:tile=$2 extra="" ;;
    dynamic) b=queue:tile=$2 extra="" ;;  # the paper's form (pipeline=paper, the default)
    deep) b=queue:tile=$2:pipeline=deep extra="--depth 2" ;;  # ours, depth 2
    deep-auto) b=queue:tile=$2:pipeline=deep extra="--depth auto" ;;  # ours, adapting
    hybrid) b=hybrid extra="--depth auto" ;;
  esac
}

if part B; then
for link in $links; do
  echo "== B. Seo Table 9 on the emulated $link link: S, then frame ms and efficiency tau_1/(S tau_S)"
  printf "%-14s" "strategy"
  for s in $workers; do printf "%18s" "S=$s"; done
  echo
  for r in $(seq "$repeats"); do
  for strategy in $strategies; do
    seo_strategy $strategy 64
    printf "%-14s" "$strategy"
    t1=""
    for s in $workers; do
      t=$(seo_run $s $link $b $extra)
      [ -z "$t1" ] && t1=$t
      printf "%11s ms %4s" "$t" "$(awk -v a="$t1" -v b="$t" -v s=$s 'BEGIN { printf "%.2f", a / (s * b) }')"
    done
    echo
  done
  done
done | tee "$out/seo_table9.txt"
fi

if part C; then
echo "== C. Seo Table 8: 1024x1024, emulated wifi, frame ms by tile size" | tee "$out/seo_table8.txt"
for s in $table8_workers; do
  for r in $(seq "$repeats"); do
  for strategy in ${TABLE8_STRATEGIES:-static dynamic deep}; do
    printf "S=%-3s %-8s" "$s" "$strategy"
    for tile in 32 64 128 256; do
      seo_strategy $strategy $tile
      printf "%12s" "$(res=1024x1024 seo_run $s wifi $b $extra)"
    done
    echo
  done
  done
done | tee -a "$out/seo_table8.txt"
fi

if part D; then
echo "== D. Harada's hierarchy: 3 ranks of 2, 1 and 1 emulated devices, fixed camera" | tee "$out/harada.txt"
for r in $(seq "$repeats"); do
for pair in "semi-static semi-static" "semi-static hybrid" "hybrid hybrid"; do
  set -- $pair
  dir="$out/harada"
  $mpirun -np 4 "$bin" render --distributed --res 256x256 --spp 1 --bounces 3 --frames 20 \
    --balancer "$1" --rank-balancer "$2" \
    --rank-devices 1=cpu:threads=1:speed=0.2,cpu:threads=1:speed=0.1 \
    --rank-devices 2=cpu:threads=1:speed=0.15 --rank-devices 3=cpu:threads=1:speed=0.075 \
    -q --out "$dir" --overwrite 2> /dev/null
  printf "master %-12s ranks %-12s deviation over the 4 devices %s, over the 3 ranks %s, frame %s ms\n" \
    "$1" "$2" "$(mean leaf_deviation 5 19 < "$dir/stats.json")" \
    "$(mean deviation 5 19 < "$dir/stats.json")" "$(mean frame_ms 5 19 < "$dir/stats.json")" \
    | tee -a "$out/harada.txt"
done
done
fi

if part E; then
echo "== E. a worker slowing down mid-run: 3 workers at emulated speed 0.5, worker 2 to 0.15 from frame 8" \
  | tee "$out/slow_worker.txt"
for balancer in semi-static hybrid queue:tile=32; do
  dir="$out/slow"
  $mpirun -np 4 "$bin" render --distributed --res 512x512 --spp 1 --bounces 3 --frames 20 \
    --devices cpu:threads=1:speed=0.5 --perturb 8:1:0.15 --balancer "$balancer" \
    -q --out "$dir" --overwrite 2> /dev/null
  printf "%-16s frame ms 4..7 %9s, 8..9 %9s, 12..19 %9s; imbalance 12..19 %s\n" "$balancer" \
    "$(mean frame_ms 4 7 < "$dir/stats.json")" "$(mean frame_ms 8 9 < "$dir/stats.json")" \
    "$(mean frame_ms 12 19 < "$dir/stats.json")" "$(mean imbalance 12 19 < "$dir/stats.json")" \
    | tee -a "$out/slow_worker.txt"
done
fi
