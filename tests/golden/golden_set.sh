# What the golden images are: sourced by tests/golden/test_golden.sh (compares) and
# scripts/regen-goldens (writes). Both render through `houle render --raw` in rgb24, the bytes the
# PNG writer encodes too, so cross builds without OpenImageIO produce the same images. A golden is one
# PNG per scene, its frames stacked top to bottom (tests/golden/<scene>.png, 128 x 216).
golden_size=128x72
golden_width=128 golden_height=72
# Frames 0..2 at 2 fps: t = 0, 0.5 and 1 s (frame n shows t = n / fps).
golden_fps=2
golden_frames=0:2
golden_count=3
# The paper's three plates and the built-in coast (no scene file).
golden_scenes=(paper_plate1 paper_plate2_noise paper_plate3 coast)

# golden_scene_args <source dir> <name>: the scene argument of `houle render` for a golden name.
golden_scene_args() {
  [ "$2" = coast ] || echo "$1/scenes/$2.toml"
}

# golden_render <source dir> <name> <out.rgb> <houle command...>: the golden frames of one scene as
# raw rgb24, at the default quality (realtime) and thread count.
golden_render() {
  local src=$1 name=$2 out=$3; shift 3
  "$@" render $(golden_scene_args "$src" "$name") --size "$golden_size" --fps "$golden_fps" \
    --frames "$golden_frames" --raw "$out" --quiet
}

# golden_strip_ppm <in.rgb> <out.ppm>: a raw rgb24 run (frames one after the other, top row first) is
# the frames stacked top to bottom; as a binary PPM, which OpenImageIO reads.
golden_strip_ppm() {
  { printf 'P6\n%d %d\n255\n' "$golden_width" $((golden_height * golden_count)); cat "$1"; } >"$2"
}
