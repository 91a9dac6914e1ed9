#include "io/video.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>
#include <vector>

#include "core/error.h"
#include "core/exclusive_file.h"
#include "core/process.h"
#include "core/temp_files.h"
#include "io/atomic_file.h"

namespace nsf {

namespace fs = std::filesystem;

namespace {

std::string read_all(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Runs one ffmpeg encode and moves the result to `out`; "" on success, else ffmpeg's messages.
// ffmpeg writes by name, so it writes into a private directory (core/exclusive_file.h) where no
// one can plant a link; the bytes then reach `out` through an exclusively created temp file. The
// file names go to ffmpeg as separate arguments, never through a shell, so any character in them
// is safe; made absolute, none can be read as an option ("-x") or a protocol ("pipe:").
std::string run_ffmpeg(const std::string& ffmpeg, const VideoJob& job, const std::string& out,
                       const std::string& format, const std::vector<std::string>& codec_args) {
  const PrivateDir work("nsf_video");
  const std::string encoded = work.path("video." + format), log = work.path("ffmpeg.log");
  std::vector<std::string> argv = {ffmpeg, "-nostdin", "-y", "-hide_banner", "-loglevel", "error"};
  argv.insert(argv.end(), {"-framerate", std::to_string(job.fps), "-start_number", "0"});
  argv.insert(argv.end(), {"-i", fs::absolute(job.pattern).string()});
  argv.insert(argv.end(), {"-frames:v", std::to_string(job.frame_count)});
  argv.insert(argv.end(), codec_args.begin(), codec_args.end());
  argv.insert(argv.end(), {"-f", format, encoded});
  const TempFileRegistration registration(encoded);  // a fatal signal deletes it
  const int status = run_program(argv, log);
  if (status != 0) {
    std::string message = read_all(log);
    if (message.empty())
      message = status < 0 ? "ffmpeg could not be started (" + ffmpeg + ")"
                           : "ffmpeg exited with status " + std::to_string(status);
    return message;
  }
  write_file_atomic(out, read_file_bytes(encoded));
  return "";
}

}  // namespace

VideoResult encode_video(const std::string& ffmpeg, const VideoJob& job) {
  if (job.frame_count <= 0) fail("video: no frames to encode");
  std::string mp4_error;
  if (!job.gif) {
    // yuv420p needs even sizes: pad by a pixel rather than rescale and blur the legend.
    const std::string out = job.out_stem + ".mp4";
    mp4_error = run_ffmpeg(ffmpeg, job, out, "mp4",
                           {"-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-pix_fmt",
                            "yuv420p", "-crf", "20", "-movflags", "+faststart"});
    if (mp4_error.empty()) return {out, ""};
  }
  // One palette for the whole animation, so colours do not flicker between frames.
  const std::string out = job.out_stem + ".gif";
  const std::string gif_error = run_ffmpeg(
      ffmpeg, job, out, "gif",
      {"-filter_complex", "split[a][b];[a]palettegen=stats_mode=full[p];[b][p]paletteuse"});
  if (gif_error.empty()) return {out, mp4_error};
  fail("video: ffmpeg failed", mp4_error.empty() ? "" : " (MP4: " + mp4_error + ")",
       "; GIF: ", gif_error);
}

}  // namespace nsf
