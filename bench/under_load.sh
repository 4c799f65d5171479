#!/bin/sh
# The wheel under a competing load: two `yes > /dev/null` take both cores of a two-core
# machine while a run with the default threads and one with `--threads 1` alternate; the
# default must not be slower than one thread. Then two default runs side by side against one.
#
# usage: bench/under_load.sh [BINARY] [SCENARIO] [PAIRS]
#   BINARY   default target/release/softway
#   SCENARIO default scenarios/wheel.toml
#   PAIRS    alternated pairs of runs, default 3
# Prints every run's wall seconds and the median ratios; the `yes` processes are killed on exit.
set -eu
bin=${1:-target/release/softway}
scenario=${2:-scenarios/wheel.toml}
pairs=${3:-3}
out=$(mktemp -d)
yes > /dev/null & y1=$!
yes > /dev/null & y2=$!
trap 'kill $y1 $y2 2>/dev/null; rm -rf "$out"' EXIT INT TERM

# Wall seconds of one command.
wall() {
    t0=$(date +%s.%N)
    "$@" > /dev/null 2>&1
    t1=$(date +%s.%N)
    awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f\n", b - a }' 
}

run() {
    dir=$1
    shift
    "$bin" run "$scenario" --quiet --force --out "$out/$dir" "$@"
}
two() { run a & p=$!; run b; wait $p; }

: > "$out/ratios"
: > "$out/side"
i=0
while [ "$i" -lt "$pairs" ]; do
    d=$(wall run default)
    s=$(wall run one --threads 1)
    echo "pair $i: default $d s, --threads 1 $s s"
    awk -v a="$d" -v b="$s" 'BEGIN { print a / b }' >> "$out/ratios"
    w2=$(wall two)
    w1=$(wall run single)
    echo "pair $i: two side by side $w2 s, one $w1 s"
    awk -v a="$w2" -v b="$w1" 'BEGIN { print a / b }' >> "$out/side"
    i=$((i + 1))
done
median() { sort -g "$1" | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
echo "median wall ratio default / --threads 1: $(median "$out/ratios")"
echo "median wall ratio two side by side / one: $(median "$out/side")"
