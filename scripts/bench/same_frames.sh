#!/usr/bin/env bash
# Renders the sampling models' frames with two fovlab binaries and compares what they write byte for
# byte: the linear frame (.exr), the step heat map and the samples-per-pixel image. For a speed
# change that must keep every frame (and so every logged frame hash) as it was (issue 41).
#
#   scripts/bench/same_frames.sh OLD_FOVLAB NEW_FOVLAB OUT_DIR
#
# The cases: rmfr on primitives and columns at four gazes and three sigmas (640x360), kfr, hyperbolic
# and linear at two gazes, rmfr at 1280x720 and at 4 spp, and the Lanczos read of rmfr, kfr and
# hyperbolic. Prints one line a case and the counts; exit status 1 when any case differs or fails.
set -u
if (($# != 3)); then
  echo "usage: $0 OLD_FOVLAB NEW_FOVLAB OUT_DIR" >&2
  exit 2
fi
old=$1 new=$2 out=$3
mkdir -p "$out/old" "$out/new"
cases=()
for scene in primitives columns; do
  for gaze in "320,180" "40,300" "600,20" "213.7,91.3"; do
    for sigma in 2.6 1.5 4; do cases+=("$scene|rmfr|$gaze|--sigma $sigma"); done
  done
  for gaze in "320,180" "40,300"; do
    for method in kfr hyperbolic linear; do cases+=("$scene|$method|$gaze|"); done
  done
done
cases+=("primitives|rmfr|640,360|--sigma 2.6 --width 1280 --height 720")
cases+=("primitives|rmfr|320,180|--sigma 2.6 --spp 4")
for method in rmfr kfr hyperbolic; do
  cases+=("primitives|$method|320,180|--resample lanczos")
  cases+=("columns|$method|40,300|--resample lanczos")
done
same=0 differ=0
for case in "${cases[@]}"; do
  IFS='|' read -r scene method gaze extra <<<"$case"
  size=(--width 640 --height 360)
  [[ "$extra" == *--width* ]] && size=()
  name=$(echo "$scene $method $gaze $extra" | tr -s ' ,.' '_')
  ok=1
  for which in old new; do
    binary=$old
    [[ $which == new ]] && binary=$new
    # shellcheck disable=SC2086  # $extra is a list of flags
    if ! "$binary" render --scene "$scene" --method "$method" "${size[@]}" --gaze "$gaze" $extra \
      --out "$out/$which/$name.exr" --steps-out "$out/$which/$name.steps.png" \
      --mask-out "$out/$which/$name.mask.png" >"$out/$which/$name.log" 2>&1; then
      ok=0
      echo "FAILED $which $name (log: $out/$which/$name.log)"
    fi
  done
  for file in "$name.exr" "$name.steps.png" "$name.mask.png"; do
    cmp -s "$out/old/$file" "$out/new/$file" || ok=0
  done
  if ((ok)); then
    same=$((same + 1))
    echo "same    $name  sha256 $(sha256sum <"$out/new/$name.exr" | cut -c1-16)"
  else
    differ=$((differ + 1))
    echo "DIFFERS $name"
  fi
done
echo "identical: $same, differing or failed: $differ"
((differ == 0))
