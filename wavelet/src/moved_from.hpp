#pragma once
// The pimpl classes' (CwtTransform, RidgeFrequencyEstimator) guard against use
// after a move, which leaves no Impl: std::logic_error, not a null dereference.

#include <memory>
#include <stdexcept>
#include <string>

namespace podid::wavelet::internal {

template <class Impl>
Impl& CheckedImpl(const std::unique_ptr<Impl>& impl, const char* owner) {
  if (impl == nullptr) {
    throw std::logic_error(std::string(owner) + ": used after being moved from (assign it first)");
  }
  return *impl;
}

}  // namespace podid::wavelet::internal
