#include "app/output/video.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <initializer_list>
#include <stdexcept>
#include <system_error>
#include <vector>

#include "app/output/external_program.h"
#include "app/output/interrupt.h"
#include "io/atomic_file.h"
#include "io/number_text.h"

namespace fs = std::filesystem;

namespace wobble {

namespace {

constexpr int kEncoderThreads = 4;

std::optional<fs::path> findFfmpeg(const fs::path& frames_dir) {
  const auto ffmpeg = findProgram("ffmpeg");
  if (!ffmpeg)
    std::fprintf(stderr,
                 "wobble: ffmpeg not found on PATH: no video; the frames are in %s (install ffmpeg, "
                 "e.g. ./setup.sh, then `wobble video %s`)\n",
                 frames_dir.c_str(), frames_dir.parent_path().c_str());
  return ffmpeg;
}

std::string rateOf(double fps) { return io::formatNumber(fps, io::kRoundTripDigits); }

// The whole ffmpeg command: quiet, no prompts, the given input, then H.264 (x264 veryfast, CRF 20), yuv420p at even
// dimensions, MP4 into `temp` ("-f mp4": the temporary name needs no extension); `frames` > 0 stops after that many.
// Passed directly (no shell), so paths need no quoting.
// x264's output depends on its thread count, by default 1.5 per CPU: a fixed count makes the same frames the same
// video on any machine. 4 is a fixed choice, not a tuned one: encoding is a small share of a rendered run.
std::vector<std::string> ffmpegCommand(const fs::path& ffmpeg, std::initializer_list<std::string> input, double fps,
                                       int frames, const fs::path& temp) {
  std::vector<std::string> args = {ffmpeg.string(), "-nostdin", "-y", "-loglevel", "error"};
  args.insert(args.end(), input);
  if (frames > 0) args.insert(args.end(), {"-frames:v", std::to_string(frames)});
  args.insert(args.end(), {"-threads", std::to_string(kEncoderThreads), "-vf", "crop=trunc(iw/2)*2:trunc(ih/2)*2",
                           "-c:v", "libx264", "-preset", "veryfast", "-crf", "20", "-pix_fmt", "yuv420p", "-r",
                           rateOf(fps), "-f", "mp4", temp.string()});
  return args;
}

// What to do with ffmpeg's outcome: rename into place, or remove the partial file and say why.
std::optional<fs::path> settle(int status, const fs::path& temp, const fs::path& mp4) {
  std::error_code ignored;
  if (interrupted()) {  // ffmpeg was ended (or saw the terminal's Ctrl-C itself): no video, no partial file
    fs::remove(temp, ignored);
    return std::nullopt;
  }
  if (status != 0) {
    fs::remove(temp, ignored);
    throw std::runtime_error("ffmpeg failed encoding " + mp4.string() + " (exit status " + std::to_string(status) +
                             ")");
  }
  fs::rename(temp, mp4);
  return mp4;
}

}  // namespace

std::optional<fs::path> encodeVideo(const fs::path& frames_dir, const std::string& name, int first, int last,
                                    double fps, const fs::path& mp4) {
  const auto ffmpeg = findFfmpeg(frames_dir);
  if (!ffmpeg) return std::nullopt;
  const fs::path temp = io::temporarySibling(mp4, "partial");
  const auto args = ffmpegCommand(*ffmpeg,
                                  {"-framerate", rateOf(fps), "-start_number", std::to_string(first), "-i",
                                   (frames_dir / (name + "_%04d.png")).string()},
                                  fps, last - first + 1, temp);
  return settle(runProgram(args), temp, mp4);
}

std::unique_ptr<VideoStream> VideoStream::open(const fs::path& mp4, int width, int height, double fps) {
  const auto ffmpeg = findFfmpeg(mp4.parent_path() / "frames");
  if (!ffmpeg) return nullptr;
  std::signal(SIGPIPE, SIG_IGN);  // a write to an ffmpeg that has stopped reads as EPIPE, not a silent death
  const fs::path temp = io::temporarySibling(mp4, "partial");
  const auto args =
      ffmpegCommand(*ffmpeg,
                    {"-f", "rawvideo", "-pix_fmt", "rgb24", "-video_size",
                     std::to_string(width) + "x" + std::to_string(height), "-framerate", rateOf(fps), "-i", "pipe:0"},
                    fps, 0, temp);
  const PipedProgram child = startPiped(args);
  return std::unique_ptr<VideoStream>(new VideoStream(mp4, temp, child.pid, child.input, width, height));
}

VideoStream::VideoStream(fs::path mp4, fs::path temp, int pid, int input, int width, int height)
    : mp4_(std::move(mp4)), temp_(std::move(temp)), pid_(pid), input_(input), width_(width), height_(height) {}

VideoStream::~VideoStream() { abandon(); }

void VideoStream::abandon() {
  if (input_ >= 0) ::close(input_), input_ = -1;
  if (pid_ > 0) {
    ::kill(pid_, SIGTERM);
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    pid_ = -1;
    std::error_code ignored;
    fs::remove(temp_, ignored);
  }
}

void VideoStream::write(const image::Image8& frame) {
  if (frame.width != width_ || frame.height != height_ || frame.channels != 3)
    throw std::logic_error("video: a frame of another size or channel count than the stream's");
  if (input_ < 0) return;  // ffmpeg stopped reading
  const auto* bytes = frame.pixels.data();
  std::size_t left = frame.pixels.size();
  while (left > 0) {
    const ssize_t n = ::write(input_, bytes, left);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {  // ffmpeg has stopped (its own message is on stderr): the frames go on, finish() reports it
      ::close(input_), input_ = -1;
      return;
    }
    bytes += n, left -= std::size_t(n);
  }
}

std::optional<fs::path> VideoStream::finish() {
  if (input_ >= 0) ::close(input_), input_ = -1;
  const int pid = pid_;
  pid_ = -1;
  return settle(waitProgram(pid, "ffmpeg"), temp_, mp4_);
}

}  // namespace wobble
