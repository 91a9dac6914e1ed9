#include "io/video.h"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "core/error.h"

namespace nsf {

namespace fs = std::filesystem;

namespace {

// Single quotes protect everything but a single quote, which becomes '\''.
std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string read_all(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Runs one ffmpeg encode into <out>.tmp and renames it; "" on success, else ffmpeg's messages.
std::string run_ffmpeg(const std::string& ffmpeg, const VideoJob& job, const std::string& out,
                       const std::string& format, const std::string& codec_args) {
  const std::string tmp = out + ".tmp", log = out + ".log";
  std::ostringstream cmd;
  cmd << shell_quote(ffmpeg) << " -nostdin -y -hide_banner -loglevel error -framerate " << job.fps
      << " -start_number 0 -i " << shell_quote(job.pattern) << " -frames:v " << job.frame_count
      << " " << codec_args << " -f " << format << " " << shell_quote(tmp) << " 2> "
      << shell_quote(log);
  const int status = std::system(cmd.str().c_str());
  std::string message = status == 0 ? "" : read_all(log);
  if (status != 0 && message.empty())
    message = "ffmpeg exited with status " + std::to_string(status);
  std::error_code ec;
  fs::remove(log, ec);
  if (status != 0) {
    fs::remove(tmp, ec);
    return message;
  }
  fs::rename(tmp, out, ec);
  if (ec) {
    fs::remove(tmp, ec);
    return "cannot move " + tmp + " into place: " + ec.message();
  }
  return "";
}

}  // namespace

std::string find_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  if (!path) return "";
  std::istringstream dirs(path);
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    if (dir.empty()) dir = ".";
    const fs::path p = fs::path(dir) / name;
    std::error_code ec;
    if (fs::is_regular_file(p, ec) && ::access(p.c_str(), X_OK) == 0) return p.string();
  }
  return "";
}

VideoResult encode_video(const std::string& ffmpeg, const VideoJob& job) {
  if (job.frame_count <= 0) fail("video: no frames to encode");
  std::string mp4_error;
  if (!job.gif) {
    // yuv420p needs even sizes: pad by a pixel rather than rescale and blur the legend.
    const std::string out = job.out_stem + ".mp4";
    mp4_error = run_ffmpeg(ffmpeg, job, out, "mp4",
                           "-vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' -c:v libx264 -pix_fmt yuv420p "
                           "-crf 20 -movflags +faststart");
    if (mp4_error.empty()) return {out, ""};
  }
  // One palette for the whole animation, so colours do not flicker between frames.
  const std::string out = job.out_stem + ".gif";
  const std::string gif_error = run_ffmpeg(
      ffmpeg, job, out, "gif",
      "-filter_complex \"split[a][b];[a]palettegen=stats_mode=full[p];[b][p]paletteuse\"");
  if (gif_error.empty()) return {out, mp4_error};
  fail("video: ffmpeg failed", mp4_error.empty() ? "" : " (MP4: " + mp4_error + ")",
       "; GIF: ", gif_error);
}

}  // namespace nsf
