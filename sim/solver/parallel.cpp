#include "sim/solver/parallel.h"

#include <atomic>

namespace wobble {
namespace {

std::atomic<int> threshold{4096};

}  // namespace

int parallelThreshold() { return threshold.load(std::memory_order_relaxed); }
void setParallelThreshold(int particles) { threshold.store(particles, std::memory_order_relaxed); }

}  // namespace wobble
