// Stand-in for the fmt headers PyTorch's wheel ships in torch/include (fmt 11, where romp's spdlog
// is built for Debian's fmt 9). Reaching this file means Torch's include folder shadowed romp's fmt.
#error "the stand-in Torch's fmt header was picked up ahead of romp's fmt"
