#!/bin/sh
# Split/merge on one node: N parts run concurrently with xargs -P, then
# merged. The same steps as tmc-parts.sbatch + tmc-merge.sbatch, without Slurm.
#
#   scripts/slurm/parts-local.sh INPUT N OUTPUT [extract options: --iso V ...]
#
# With --labels (a label map), OUTPUT is what tmc merge writes: 'out/{label}.ply'
# (one mesh per label) or one .ply/.tmesh of every label.
#
# Part files go to a temporary directory next to OUTPUT; TMC names the tmc
# binary (default: tmc on PATH); JOBS caps the concurrent parts (default N).
set -eu
[ $# -ge 3 ] || { echo "usage: $0 INPUT N OUTPUT [extract options]" >&2; exit 2; }
input=$1 n=$2 output=$3
shift 3
case $n in
'' | *[!0-9]* | 0*) echo "$0: N is the number of parts (1 or more), not '$n'" >&2; exit 2 ;;
esac
[ -d "$(dirname "$output")" ] || {
    echo "$0: the output's directory $(dirname "$output") does not exist (create it first)" >&2
    exit 1
}
tmc=${TMC:-tmc}
parts=$(mktemp -d "$(dirname "$output")/.tmc-parts.XXXXXX")
# EXIT alone is not enough: dash (sh on Debian) does not run the EXIT trap
# when a signal kills the shell. On SIGINT, SIGTERM or SIGHUP remove the
# parts, then exit with 128 + the signal's number, as the shell would.
trap 'rm -rf "$parts"' EXIT
trap 'rm -rf "$parts"; exit 130' INT
trap 'rm -rf "$parts"; exit 143' TERM
trap 'rm -rf "$parts"; exit 129' HUP
# A label map's parts are one file per label: tmc fills in {label} and {part}.
name='part-{}.tmesh'
for option in "$@"; do
    case $option in --labels | --labels=*) name='{label}.part-{part}.tmesh' ;; esac
done
seq 1 "$n" | xargs -P "${JOBS:-$n}" -I{} \
    "$tmc" extract "$input" -q --threads 1 --part "{}/$n" -o "$parts/$name" "$@"
"$tmc" merge "$parts"/*.tmesh -o "$output"
