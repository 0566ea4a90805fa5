#!/bin/sh
# Open MPI's rsh agent for tests/mpi/netfault.sh (`mpirun --mca plm_rsh_agent THIS`): mpirun
# runs `THIS HOST COMMAND...` where ssh would run `ssh HOST COMMAND...`. HOST is the name
# of a network namespace the harness made (mrnf-*); the command (orted and its
# environment, written for a remote shell, as ssh would pass it) runs inside that
# namespace, in a UTS namespace of its own named HOST, so that every daemon has its own
# host name and its own Open MPI session folder, as on separate machines.
set -eu
host=$1
shift
case "$host" in
  mrnf-*) ;;
  *) echo "netns_agent: '$host' is not a namespace of the network-fault harness" >&2; exit 2 ;;
esac
# ssh joins its arguments with spaces and the remote shell parses them: do the same.
exec ip netns exec "$host" unshare --uts sh -c 'hostname "$0" && exec sh -c "$1"' "$host" "$*"
