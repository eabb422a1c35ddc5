#!/bin/bash
# docs/peers.md: dalembert beside CAPD (pped2 state sets, C1Rect2Set derivatives), widths
# and CPU-time medians of N runs with the two tools alternated. DALEMBERT, CAPD_FLOW: the binaries.
# CPU-time (user+sys) medians of N runs, dalembert and CAPD alternated; widths from each tool's JSON.
N=${N:-5}
tmp=$(mktemp); trap 'rm -f "$tmp" "$tmp.t" "$tmp.json"' EXIT
DAL=${DALEMBERT:-dalembert}; CAPD=${CAPD_FLOW:-capd_flow}
q=0,0,0; u=0.8,0.8
med() { sort -g | awk '{a[NR]=$1} END{print a[int((NR+1)/2)]}'; }
cpu() { /usr/bin/time -f "%U %S" -o "$tmp.t" "$@" > "$tmp.json"; awk '{print $1+$2}' "$tmp.t"; }
one() { # label, capd args..., --, dal args...
  local label=$1; shift; local ca=(); while [ "$1" != -- ]; do ca+=("$1"); shift; done; shift
  local ta=() tb=()
  for i in $(seq $N); do
    tb+=($(cpu "$CAPD" "${ca[@]}")); cw=$(python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); print("%.3e %.3e %d" % (d["max_width"], d.get("jacobian_max_width",0), d["steps"]))' "$tmp.json")
    ta+=($(cpu "$DAL" flow "$@" --json)); dw=$(python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); print("%.3e %.3e %d" % (max(b-a for a,b in d["q"]+d["u"]), max((b-a for r in d.get("jacobian",[]) for a,b in r), default=0), d["stats"]["steps"]))' "$tmp.json")
  done
  echo "$label | dal $dw $(printf '%s\n' "${ta[@]}" | med) | capd $cw $(printf '%s\n' "${tb[@]}" | med)"
}
for c in "particle 0.5" "particle 600" "knife 50" "knife 600" "knife-eps 600"; do
  set -- $c; p=$1; T=$2; par=(); [ $p = knife-eps ] && par=(--param eps=0.1)
  one "$p $T state" $p $T pped2 $q $u -- --scene $p "${par[@]}" --q $q --u $u --t $T
done
for c in "particle 10" "particle 50" "particle 600" "knife 50" "knife 600" "knife-eps 600"; do
  set -- $c; p=$1; T=$2; par=(); [ $p = knife-eps ] && par=(--param eps=0.1)
  one "$p $T c1" $p $T c1 $q $u -- --scene $p "${par[@]}" --q $q --u $u --t $T --jacobian
done
