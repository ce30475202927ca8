// How a reduced-order model was trained, as plain values (no LibTorch): the settings that decide a training
// run's result, the data it saw and the errors it reached. The model file stores it (rom_model_file_content.h).
#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "nn/rom/map_layout.h"
#include "nn/rom/sweep_manifest.h"

namespace romp::nn::rom {

enum class DerivativeMethod {
  // Tangents pushed through the layers next to the values (one batched product per layer for 3 + m
  // directions); the result stays differentiable for training.
  Analytic,
  // One reverse pass per output component; with create_graph the loss back-propagates through them.
  Autograd,
};

const char* to_string(DerivativeMethod method);

struct LossWeights {
  double F = 100.0;        // λ_F
  double velocity = 0.01;  // λ_v
};

// Everything that decides a training run's result (with the data). A resumed run must use the same settings.
struct TrainingSettings {
  MapArchitecture architecture;        // latent r, hidden layers (0: the linear baseline), width
  std::int64_t encoder_points = 1000;  // Q (0: every point)
  std::int64_t epochs = 1000;
  std::int64_t batch = 16;    // snapshots per mini-batch
  std::int64_t points = 256;  // material points per snapshot in the loss, drawn anew each batch
  std::uint64_t seed = 0;
  LossWeights loss_weights;
  double learning_rate = 1e-3;  // the first stage's
  // Fractions of the epochs after which the learning rate drops tenfold: 1e-3 → 1e-4 → 1e-5 → 1e-6.
  std::vector<double> decay_at = {0.5, 0.75, 0.9};
  DerivativeMethod derivatives = DerivativeMethod::Analytic;

  // The learning rate of epoch `epoch` (0-based).
  double learning_rate_at(std::int64_t epoch) const;
  // "batch: 16 here, 32 in the other" for each setting that differs; empty when they agree.
  std::vector<std::string> differences(const TrainingSettings& other) const;
};

// Relative L2 errors over every point of every snapshot of a set, as the paper's position error (Sec. 5):
// ‖prediction − truth‖ / ‖truth‖, summed over points and snapshots. NaN where the set is empty (or the truth 0).
struct ReconstructionErrors {
  double position = std::numeric_limits<double>::quiet_NaN();
  double F = std::numeric_limits<double>::quiet_NaN();
  // (∂g/∂x̂)(x̂_{n+1} − x̂_n)/Δt against (x_{n+1} − x_n)/Δt; last frames excluded
  double velocity = std::numeric_limits<double>::quiet_NaN();
};

struct TrainingRecord {
  std::string sweep_dir;
  std::vector<std::string> parameter_names;
  std::vector<SweepMember> members;
  std::int64_t particle_count = 0;  // P of the training snapshots (the encoder's indices point into them)
  TrainingSettings settings;
  std::int64_t epochs_done = 0;
  ReconstructionErrors train_errors, test_errors;
  std::string romp_version, commit;  // of the romp that trained it
};

}  // namespace romp::nn::rom
