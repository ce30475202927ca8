// The training settings' learning-rate stages and comparison.
#include "nn/rom/training_record.h"

#include <sstream>

namespace romp::nn::rom {
namespace {

template <class T>
std::string text(const T& value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

std::string text(const std::vector<double>& values) {
  std::string joined;
  for (double value : values) joined += (joined.empty() ? "" : ",") + text(value);
  return joined;
}

}  // namespace

const char* to_string(DerivativeMethod method) {
  return method == DerivativeMethod::Analytic ? "analytic" : "autograd";
}

double TrainingSettings::learning_rate_at(std::int64_t epoch) const {
  double rate = learning_rate;
  for (double fraction : decay_at) {
    if (double(epoch) >= fraction * double(epochs)) rate *= 0.1;
  }
  return rate;
}

std::vector<std::string> TrainingSettings::differences(const TrainingSettings& other) const {
  std::vector<std::string> found;
  const auto compare = [&](const char* name, const auto& mine, const auto& theirs) {
    if (mine != theirs)
      found.push_back(std::string(name) + ": " + text(mine) + " here, " + text(theirs) + " in the other");
  };
  compare("latent", architecture.latent, other.architecture.latent);
  compare("hidden layers", architecture.hidden_layers, other.architecture.hidden_layers);
  compare("width", architecture.width, other.architecture.width);
  compare("encoder points", encoder_points, other.encoder_points);
  compare("epochs", epochs, other.epochs);
  compare("batch", batch, other.batch);
  compare("points", points, other.points);
  compare("seed", seed, other.seed);
  compare("lambda_F", loss_weights.F, other.loss_weights.F);
  compare("lambda_v", loss_weights.velocity, other.loss_weights.velocity);
  compare("learning rate", learning_rate, other.learning_rate);
  compare("decay at", decay_at, other.decay_at);
  compare("derivatives", std::string(to_string(derivatives)), std::string(to_string(other.derivatives)));
  return found;
}

}  // namespace romp::nn::rom
