# Sourced by the CLI tests: write_cube_scene PATH NAME writes a jelly cube scene of 6 frames (0.05 s at
# 100 fps, dx = 2 cm), a run of a few seconds on one CPU thread.
write_cube_scene() {
  cat > "$1" <<SCENE
[scene]
name = "$2"
[domain]
size = [0.2, 0.2, 0.2]
dx = 0.02
[time]
end = 0.05
frame_rate = 100
[materials.jelly]
preset = "jelly"
[[objects]]
name = "cube"
shape = { type = "box", center = [0.1, 0.1, 0.1], size = [0.06, 0.06, 0.06] }
SCENE
}
