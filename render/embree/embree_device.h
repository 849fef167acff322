// EmbreeDevice: owns an RTCDevice. Embree API used here: rtcNewDevice, rtcSetDeviceErrorFunction,
// rtcGetDeviceError, rtcReleaseDevice.
//
// Embree reports errors through a C callback, which must not throw (the exception would unwind through Embree's C
// frames). The callback records the message; check() throws it as std::runtime_error with the caller's context.
// Parameter: config, Embree's device configuration string (nullptr = defaults; e.g. "verbose=1").
#pragma once
#include <mutex>
#include <string>
#include <string_view>

#include <embree3/rtcore.h>

namespace wobble::render {

class EmbreeDevice {
 public:
  explicit EmbreeDevice(const char* config = nullptr);
  ~EmbreeDevice();
  EmbreeDevice(const EmbreeDevice&) = delete;
  EmbreeDevice& operator=(const EmbreeDevice&) = delete;

  RTCDevice get() const { return device_; }
  // Throws std::runtime_error "<what>: Embree error: <message>" if Embree reported an error since the last check.
  void check(std::string_view what) const;

 private:
  static void onError(void* self, RTCError code, const char* message);

  RTCDevice device_ = nullptr;
  mutable std::mutex mutex_;
  mutable std::string last_error_;
};

}  // namespace wobble::render
