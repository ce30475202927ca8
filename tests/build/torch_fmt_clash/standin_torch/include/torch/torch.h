// Stand-in for <torch/torch.h>: only where it lives matters (the folder that also holds fmt/).
#pragma once
