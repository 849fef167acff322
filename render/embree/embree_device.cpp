// RTCDevice ownership and error reporting (see embree_device.h).
#include "render/embree/embree_device.h"

#include <stdexcept>

namespace wobble::render {

EmbreeDevice::EmbreeDevice(const char* config) {
  device_ = rtcNewDevice(config);
  if (!device_)
    throw std::runtime_error("Embree: cannot create a device (error " + std::to_string(rtcGetDeviceError(nullptr)) +
                             "); is the CPU SSE2-capable and the Embree library installed?");
  rtcSetDeviceErrorFunction(device_, &EmbreeDevice::onError, this);
}

EmbreeDevice::~EmbreeDevice() { rtcReleaseDevice(device_); }

void EmbreeDevice::onError(void* self, RTCError code, const char* message) {
  auto* device = static_cast<EmbreeDevice*>(self);
  std::lock_guard lock(device->mutex_);
  if (device->last_error_.empty())  // keep the first error: later ones are usually consequences
    device->last_error_ = std::string(message ? message : "no message") + " (code " + std::to_string(code) + ")";
}

void EmbreeDevice::check(std::string_view what) const {
  const RTCError code = rtcGetDeviceError(device_);
  std::string message;
  {
    std::lock_guard lock(mutex_);
    message.swap(last_error_);
  }
  if (code == RTC_ERROR_NONE && message.empty()) return;
  if (message.empty()) message = "code " + std::to_string(code);
  throw std::runtime_error(std::string(what) + ": Embree error: " + message);
}

}  // namespace wobble::render
