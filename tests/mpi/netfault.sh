#!/bin/bash
# Real network faults under `multiray --distributed` (issue 53 item 10; docs/reliability.md).
#
#   tests/mpi/netfault.sh MULTIRAY MPIEXEC worker|worker-queue|master
#
# Every rank runs on a network stack of its own: a Linux network namespace per rank
# (mrnf-PID-r0 the master, -r1 and -r2 workers), each joined by a veth pair to a bridge in
# a hub namespace (mrnf-PID-hub), where mpirun runs. Open MPI starts its daemons through
# its rsh agent, set to tests/mpi/netns_agent.sh, which enters the namespace the hostfile
# names; the TCP BTL and OOB are held to the namespaces' 10.253.0.0/24. Every address
# lives inside namespaces made here: the host's interfaces and routes are not touched.
#
# A link is cut with `ip link set hN down` on the hub's side: no RST, no error, packets
# simply vanish, as when a cable is pulled or a switch port dies.
#
#   worker  rank 2's link is slowed to 2 Mbit/s (tbf), so that its result (half of a
#           320x180 frame with its feature buffers, 1.6 MB as float, in 128 KiB parts)
#           takes over 6 s to cross, longer than --worker-timeout, and cut while
#           that result is half across; restored 6 s later. The frame must complete with
#           its items re-rendered by rank 1, every frame bit-identical to one process,
#           "rank 2: no answer" printed, rank 1 never taking the master for dead, and the
#           master ending with 0.
#   worker-queue  the same cut 0.5 s into frame 1 of a tile queue (16x16 tiles: every
#           message is under Open MPI's 64 KB eager limit, so none is ever half received),
#           the workers slowed to an emulated speed of 0.01 so that frames last ~1.5 s;
#           the same checks.
#   master  the master's own link is cut mid-frame. The master cannot finish without its
#           workers: it must end by itself within --worker-timeout and a few seconds,
#           non-zero, naming every rank it lost; each worker ends likewise, saying it heard
#           nothing from the master. (mpirun itself learns that only once the link is
#           back: its daemon on the master's side cannot tell it, so the link is restored
#           after the ranks ended, and mpirun must end within 30 s of it.)
#
# Exit 0: passed; 1: failed (what failed is printed); 77: skipped, with the reason (not
# root, no `ip`/`unshare`/`tc`, or no namespace can be made here). Every step has a
# deadline: a passing run takes 10-30 s (the worker cut's frame 0 waits about 12 s for
# rank 2's whole result), a failing one ends within about 80 s. Only the
# processes inside these namespaces (all started here) are killed, by PID, and the
# namespaces (and with them their veths) are deleted on every exit, a failed or
# interrupted one too; a failed run keeps its logs and says where.
set -u
[ $# -eq 3 ] || { sed -n '2,40p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
multiray=$1
mpiexec=$2
scenario=$3
agent="$(cd "$(dirname "$0")" && pwd)/netns_agent.sh"
timeout_s=2 # --worker-timeout
P=mrnf-$$
start=$(date +%s.%N)

say() { printf 'netfault %s [%5.1f s]: %s\n' "$scenario" "$(echo "$(date +%s.%N) - $start" | bc)" "$*"; }
skip() {
  echo "SKIPPED: $*"
  exit 77
}
failed=0
fail() {
  say "FAILED: $*"
  failed=1
}

[ "$(id -u)" = 0 ] || skip "network namespaces need root (CAP_NET_ADMIN)"
for tool in ip unshare tc timeout bc; do
  command -v "$tool" > /dev/null || skip "no '$tool' on this machine"
done
case "$scenario" in worker | worker-queue | master) ;; *)
  echo "netfault: unknown scenario '$scenario'" >&2
  exit 2
  ;;
esac

work=$(mktemp -d "${TMPDIR:-/tmp}/$P.XXXXXX")
namespaces=()
mpirun_pid=""
cleanup() {
  # Only what runs inside our namespaces (mpirun, its daemons, the ranks: all started
  # here), by PID; then the namespaces, which takes their veths with them.
  [ -n "$mpirun_pid" ] && kill -9 "$mpirun_pid" 2> /dev/null
  for ns in "${namespaces[@]}"; do
    for pid in $(timeout 5 ip netns pids "$ns" 2> /dev/null); do kill -9 "$pid" 2> /dev/null; done
  done
  for ns in "${namespaces[@]}"; do timeout 5 ip netns del "$ns" 2> /dev/null; done
  # Open MPI's session folders of daemons killed here (named after our host names).
  rm -rf "/tmp/ompi.$P-"* "${TMPDIR:-/tmp}/ompi.$P-"*
  if [ "$failed" = 0 ]; then rm -rf "$work"; else echo "netfault: logs kept in $work"; fi
}
trap cleanup EXIT
trap 'failed=1; exit 130' INT TERM

# --- the network: a hub with a bridge, a namespace per rank, 10.253.0.(R+1)/24 ----------
net() { timeout 5 ip "$@"; }
if ! net netns add "$P-hub" 2> "$work/netns.err"; then
  skip "cannot make a network namespace here: $(head -n 1 "$work/netns.err")"
fi
namespaces+=("$P-hub")
net -n "$P-hub" link set lo up
net -n "$P-hub" link add br0 type bridge || skip "no bridge device here"
net -n "$P-hub" addr add 10.253.0.254/24 dev br0
net -n "$P-hub" link set br0 up
: > "$work/hosts"
for r in 0 1 2; do
  ns=$P-r$r
  net netns add "$ns" || skip "cannot make namespace $ns"
  namespaces+=("$ns")
  net -n "$P-hub" link add "h$r" type veth peer name e0 netns "$ns" || skip "no veth pair here"
  net -n "$P-hub" link set "h$r" master br0 up
  net -n "$ns" addr add "10.253.0.$((r + 1))/24" dev e0
  net -n "$ns" link set e0 up
  net -n "$ns" link set lo up
  echo "$ns slots=1" >> "$work/hosts"
done

# --- the run ---------------------------------------------------------------------------
if [ "$scenario" = worker ]; then
  args="render --res 320x180 --spp 1 --frames 4 --camera-path orbit:10 --balancer uniform"
  # The denoiser's feature buffers (on by default under 256 spp) make rank 2's result
  # 1.6 MB, over 6.5 s across this link, longer than --worker-timeout: sent whole, its
  # heartbeats waited behind it and the master gave rank 2 up during frame 0, before any
  # cut (a fresh clone, 2026-12-04). It crosses in parts now (distributed/transport.h).
  args+=" --result-encoding float"
  devices=cpu:threads=1
  timeout 5 ip netns exec "$P-r2" tc qdisc add dev e0 root tbf rate 2mbit burst 32kbit latency 400ms ||
    skip "no tbf qdisc here"
elif [ "$scenario" = worker-queue ]; then
  args="render --res 320x180 --spp 1 --frames 4 --camera-path orbit:10 --balancer queue:tile=16"
  devices=cpu:threads=1:speed=0.01
else
  args="render --res 320x180 --spp 2 --frames 3 --camera-path orbit:10 --balancer queue:tile=16"
  devices=cpu:threads=1:speed=0.01
fi
ref="$work/reference"
timeout 30 "$multiray" $args -q --devices cpu:threads=1 --out "$ref" > "$work/reference.log" 2>&1 ||
  {
    fail "the one-process reference did not render: $(tail -n 1 "$work/reference.log")"
    exit 1
  }
out="$work/distributed"
# Each rank's exit code goes to a file: with --enable-recovery mpirun itself returns 0
# whatever the ranks returned.
timeout -k 2 80 ip netns exec "$P-hub" "$mpiexec" --allow-run-as-root --hostfile "$work/hosts" \
  --mca plm_rsh_agent "$agent" --mca btl self,tcp --mca btl_tcp_if_include 10.253.0.0/24 \
  --mca oob_tcp_if_include 10.253.0.0/24 --enable-recovery -np 3 --map-by node \
  sh -c '"$@"; rc=$?; echo $rc > '"$work"'/rc.$OMPI_COMM_WORLD_RANK; exit $rc' sh \
  "$multiray" $args --devices "$devices" --worker-timeout $timeout_s --distributed \
  --out "$out" > "$work/mpirun.log" 2>&1 &
mpirun_pid=$!

# wait_for SECONDS WHAT COMMAND...: polls COMMAND every 50 ms; false after SECONDS.
wait_for() {
  local until
  until=$(echo "$(date +%s.%N) + $1" | bc)
  shift
  local what=$1
  shift
  while ! "$@"; do
    if [ "$(echo "$(date +%s.%N) > $until" | bc)" = 1 ]; then
      fail "no $what in time"
      return 1
    fi
    sleep 0.05
  done
}
tx_bytes() { timeout 5 ip netns exec "$P-r2" cat /sys/class/net/e0/statistics/tx_bytes; }
sent_since() { [ $(($(tx_bytes) - $1)) -gt "$2" ]; }
rank_alive() { # a multiray process still runs in rank R's namespace
  local pids
  pids=$(timeout 5 ip netns pids "$P-r$1" | tr '\n' ',')
  [ -n "$pids" ] && ps -o comm= -p "${pids%,}" | grep -q '^multiray'
}
ranks_ended() { ! rank_alive 0 && ! rank_alive 1 && ! rank_alive 2; }
mpirun_ended() { ! kill -0 "$mpirun_pid" 2> /dev/null; }
in_log() { grep -q -- "$1" "$work/mpirun.log"; }
# mpirun itself may outlive the ranks: Open MPI's daemon behind a link that was down does
# not always hear that its rank ended (docs/reliability.md). What this test judges is the
# ranks' ends; mpirun gets 30 s more, then is stopped (it is ours, by PID), and says so.
settle_mpirun() {
  local until=$(($(date +%s) + 30))
  while ! mpirun_ended; do
    if [ "$(date +%s)" -ge "$until" ]; then
      say "mpirun still running 30 s after the ranks (Open MPI's daemon): stopped"
      kill -9 "$mpirun_pid" 2> /dev/null
      return 0
    fi
    sleep 0.05
  done
  say "mpirun ended"
}

wait_for 40 "first frame" test -f "$out/frame_0000.png" || exit 1
say "frame 0 written"
if [ "$scenario" != master ]; then
  if [ "$scenario" = worker ]; then
    # Mid-frame and mid-message: rank 2's result for frame 1 is half across.
    base=$(tx_bytes)
    wait_for 10 "result of rank 2 under way" sent_since "$base" 100000 || exit 1
    net -n "$P-hub" link set h2 down
    say "rank 2's link cut ($(($(tx_bytes) - base)) bytes of its result sent)"
  else
    sleep 0.5
    net -n "$P-hub" link set h2 down
    say "rank 2's link cut"
  fi
  cut=$(date +%s.%N)
  # What is judged is the cut: a rank given up on before it judges nothing.
  in_log "rank 2: no answer" && fail "the master gave rank 2 up before its link was cut"
  wait_for $((timeout_s + 6)) "'rank 2: no answer' from the master" in_log "rank 2: no answer" &&
    say "the master gave rank 2 up"
  # Restored once the master has given up (--worker-timeout after the cut) and a few
  # seconds more: a master stuck on the half-received message would leave rank 1 without
  # heartbeats for longer than --worker-timeout by then.
  sleep "$(echo "$cut + $timeout_s + 4 - $(date +%s.%N)" | bc | sed 's/^-.*/0/')"
  net -n "$P-hub" link set h2 up
  say "rank 2's link restored"
  wait_for 30 "end of the master" test -f "$work/rc.0" && say "the master ended"
  settle_mpirun
  [ "$(cat "$work/rc.0" 2> /dev/null)" = 0 ] ||
    fail "the master ended with '$(cat "$work/rc.0" 2> /dev/null)', not 0"
  in_log "rank 1: nothing from the master" &&
    fail "rank 1, whose link was never cut, took the master for dead"
  if [ -f "$out/stats.json" ]; then
    grep -o '"image_hash": *"[^"]*"' "$ref/stats.json" > "$work/want"
    grep -o '"image_hash": *"[^"]*"' "$out/stats.json" > "$work/got"
    [ "$(wc -l < "$work/want")" = 4 ] && cmp -s "$work/want" "$work/got" ||
      fail "frames differ from one process's: $(tr '\n' ' ' < "$work/got")"
  else
    fail "no stats.json"
  fi
else
  sleep 0.5
  net -n "$P-hub" link set h0 down
  cut=$(date +%s.%N)
  say "the master's link cut"
  # The ranks end by themselves: the master and the workers each hear nothing for
  # --worker-timeout.
  wait_for $((timeout_s + 8)) "end of every rank" ranks_ended &&
    say "every rank ended, $(echo "$(date +%s.%N) - $cut" | bc | cut -c1-4) s after the cut"
  net -n "$P-hub" link set h0 up
  say "the master's link restored"
  settle_mpirun
  rc0=$(cat "$work/rc.0" 2> /dev/null)
  [ -n "$rc0" ] && [ "$rc0" != 0 ] || fail "the master ended with '$rc0', not an error"
  in_log "every device has failed: rank 1: no answer.*; rank 2: no answer" ||
    fail "the master's last line does not name both ranks it lost"
  for r in 1 2; do
    in_log "rank $r: nothing from the master" || fail "rank $r did not say why it ended"
  done
fi
if [ "$failed" != 0 ]; then
  echo "--- mpirun's output"
  grep -v "PMIX ERROR: BAD-PARAM\|setpgid" "$work/mpirun.log"
  exit 1
fi
say "passed"
grep -v "PMIX ERROR: BAD-PARAM\|setpgid" "$work/mpirun.log" | grep "rank [0-9]:"
exit 0
