# Sourced by the test scripts and .ci/run: `stage NAME COMMAND...` runs COMMAND, prints its wall time,
# and keeps it for the table `stage_summary` prints (at exit, when a script calls `trap stage_summary EXIT`).
# A failing stage's status is returned; the table says which stage failed.
stage_rows=()
stage() {
  local name=$1
  shift
  local start=$SECONDS rc=0
  echo "==> $name: $*"
  "$@" || rc=$?
  local s=$((SECONDS - start))
  stage_rows+=("$(printf '%-34s %3dm %02ds%s' "$name" $((s / 60)) $((s % 60)) "$([ $rc -eq 0 ] || echo "   FAILED (exit $rc)")")")
  echo "==> $name: $((s / 60))m $((s % 60))s, exit $rc"
  return $rc
}
stage_summary() {
  local rc=$?
  ((${#stage_rows[@]})) || return $rc
  echo "==> wall time of each stage ($(basename "$0")):"
  printf '    %s\n' "${stage_rows[@]}"
  return $rc
}
