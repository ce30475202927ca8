// cosine_anneal and teacher_forcing_period.
#include "nn/nclaw/training_schedule.h"

#include <cmath>

namespace romp::nn::nclaw {

double cosine_anneal(double first, double last, int64_t epoch, int64_t epochs) {
  const double pi = std::acos(-1.0);
  return last + (first - last) * 0.5 * (1.0 + std::cos(pi * double(epoch) / double(epochs)));
}

int64_t teacher_forcing_period(int64_t first, int64_t last, int64_t epoch, int64_t epochs) {
  return std::llround(cosine_anneal(double(first), double(last), epoch, epochs));
}

}  // namespace romp::nn::nclaw
