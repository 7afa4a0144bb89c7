#!/usr/bin/env bash
# Soak test (CTest label "soak", not in the default run): plays a scene in bsdeform-viewer under
# Xvfb for BSDEFORM_SOAK_MINUTES (default 10) and checks that the viewer stays alive and its
# resident memory stays flat: after a warm-up of a fifth of the time, RSS may grow by at most
# max(8 MB, 5 %). Usage: soak.sh VIEWER SCENE
set -euo pipefail
viewer="$1" scene="$2"
minutes="${BSDEFORM_SOAK_MINUTES:-10}"
total=$((minutes * 60))
interval=5
work="$(mktemp -d)"
trap 'kill "$(cat "$work/pid" 2>/dev/null)" 2>/dev/null || true; sleep 1; rm -rf "$work"' EXIT
export XDG_DATA_HOME="$work" XDG_CONFIG_HOME="$work" XDG_RUNTIME_DIR="$work"
xvfb-run -a -s "-screen 0 1280x1024x24" sh -c \
  "'$viewer' '$scene' --discard-recovery --autosave-interval 0 & echo \$! > '$work/pid'; wait" \
  > "$work/viewer.log" 2>&1 &
for _ in $(seq 50); do [ -s "$work/pid" ] && break; sleep 0.2; done
pid="$(cat "$work/pid")"
rss() { awk '/^VmRSS:/ {print $2}' "/proc/$pid/status" 2>/dev/null || echo 0; }
warmup=$((total / 5))
start=""
samples=()
for ((t = interval; t <= total; t += interval)); do
  sleep "$interval"
  if ! kill -0 "$pid" 2>/dev/null; then
    echo "soak: the viewer died after about ${t} s"; cat "$work/viewer.log"; exit 1
  fi
  kb="$(rss)"
  samples+=("${t}s:$((kb / 1024))MB")
  if [ -z "$start" ] && [ "$t" -ge "$warmup" ]; then start="$kb"; fi
done
end="$(rss)"
echo "soak: $scene for ${minutes} min; RSS ${samples[*]}"
allowed=$((start / 20 > 8192 ? start / 20 : 8192))
growth=$((end - start))
echo "soak: RSS after warm-up $((start / 1024)) MB, at the end $((end / 1024)) MB, growth ${growth} kB (allowed ${allowed} kB)"
[ "$growth" -le "$allowed" ]
