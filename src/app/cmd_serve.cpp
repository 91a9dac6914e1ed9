// `nsf serve MODEL SCENE`: runs the reduced-order model and streams, per frame, the latent ẑ, the
// deformation coefficients c_x(ẑ), the time and the colliders' poses over WebSocket to any number
// of clients, which may move a collider; GET / serves a page that draws it (docs/SERVE.md).
#include <chrono>
#include <cstdio>
#include <iostream>
#include <iterator>
#include <map>
#include <memory>

#include "app/commands.h"
#include "app/common_options.h"
#include "app/serve_page.h"
#include "app/serve_protocol.h"
#include "core/error.h"
#include "mpm/colliders/collider_limits.h"
#include "mpm/colliders/rigid_collider.h"
#include "net/ws_server.h"
#include "nn/basis_decoders.h"
#include "nn/torch_settings.h"
#include "rom/setup/rom_setup.h"
#include "rom/setup/scene_file.h"
#include "rom/step/latent_stepper.h"
#include "rom/step/rigid_frames.h"
#include "rom/step/step_guard.h"

namespace nsf::app {

namespace {

struct ServeArgs {
  std::string model, scene;
  std::optional<double> mu;
  std::vector<std::string> overrides;
  int samples = 0, threads = 0;
  bool quiet = false;
  net::ServerOptions net;
  double fps = -1;  // < 0: real time
  long frames = 0;  // 0: forever
  // At the scene's last frame: start it again ("loop"), keep streaming its last pose ("hold"), or
  // go on stepping past it ("continue").
  std::string at_end = "loop";
  // Bytes of the basis per message: the model message carries rest, mean and the leading modes
  // that fit, and basis messages bring the others, one whenever the client has taken the last.
  size_t basis_message_bytes = size_t(256) << 10;
};

double wall_now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}
double mono_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

class Server {
 public:
  // The scene file is read once: a reset starts the scene the server started with, whatever
  // happens to the file on disk meanwhile (an edit used to end the server at the next reset).
  explicit Server(const ServeArgs& a)
      : a_(a),
        fields_(NeuralFields::load(a.model)),
        file_(read_scene_file(a.scene, a.overrides)),
        net_(a.net) {
    if (!fields_.bases())
      fail(a.model,
           ": nsf serve streams the coefficients of a per-point basis model; this one has "
           "MLP decoders (train it with --decoder basis, the default)");
    if (a.samples > 0) choices_.samples = a.samples;
    stepper_ = start_scene();  // errors name the file and end the command, before serving
    guard_ = std::make_unique<StepGuard>(*stepper_);
    encode_basis();
    net_.set_page(serve_page());
    net_.on_open = [this](int id) {
      net_.send(id, model_, true);
      if (last_) net_.send(id, last_, true);
      if (!basis_.empty()) basis_due_[id] = 0;
      max_clients_ = std::max(max_clients_, net_.client_count());
    };
    net_.on_message = [this](int id, const std::string& text) { return receive(id, text); };
    net_.log = [this](const std::string& line) { say(line); };
    if (net_.max_clients() < a.net.max_clients)
      say("nsf serve: --max-clients " + std::to_string(a.net.max_clients) + " lowered to " +
          std::to_string(net_.max_clients()) +
          ", what the process's descriptor limit leaves free (ulimit -n " +
          std::to_string(net_.fd_limit()) + "); more clients are answered 503");
  }

  int port() const { return net_.port(); }

  void run() {
    const double fps = a_.fps < 0 ? 1.0 / frame_time_ : a_.fps;
    const double start = mono_now();
    double last_status = start, stepping = 0;
    for (long frame = 0;; ++frame) {
      last_ = net::WsServer::binary_message(
          frame_message(uint32_t(frame), stepper_->time(), wall_now(), stepper_->latent(),
                        coefficients(), poses(), float(guard_->health().indicator), rigid_poses()));
      net_.broadcast(last_);
      if (a_.frames > 0 && frame >= a_.frames) break;
      // Serve the sockets until the next frame is due (at once, with --fps 0).
      const double due = fps > 0 ? start + double(frame + 1) / fps : 0;
      do {
        net_.poll(std::max(0, int(1000 * (due - mono_now()))));
        send_basis();
      } while (mono_now() < due);
      apply_commands();
      commands_this_frame_.clear();
      const double t0 = mono_now();
      advance(frame);
      stepping += mono_now() - t0;
      if (!a_.quiet && mono_now() - last_status > 10) {
        last_status = mono_now();
        std::cerr << "nsf serve: frame " << frame + 1 << ", " << net_.client_count() << " clients, "
                  << status(frame + 1, stepping, last_status - start) << std::endl;
      }
    }
    std::cout << "nsf serve: " << a_.frames << " frames, "
              << status(a_.frames, stepping, mono_now() - start) << ", at most " << max_clients_
              << " clients" << std::endl;
  }

 private:
  // What a client learns once, beside the bases: the scene's timing, colliders and limits.
  nlohmann::json model_info() const {
    nlohmann::json info;
    info["scene"] = fields_.scene_name();
    info["latent_dim"] = fields_.latent_dim();
    info["frame_time"] = frame_time_;
    info["frames"] = frames_;
    info["at_end"] = a_.at_end;
    info["steps_per_frame"] = stepper_->steps_per_frame();
    info["mu"] = mu_;
    info["colliders"] = file_.json.value("colliders", nlohmann::json::array());
    info["domain"] = {file_.json["simulation"].value("domain_lo", nlohmann::json()),
                      file_.json["simulation"].value("domain_hi", nlohmann::json())};
    info["collider_bounds"] = {{limits_.lo[0], limits_.lo[1], limits_.lo[2]},
                               {limits_.hi[0], limits_.hi[1], limits_.hi[2]}};
    info["collider_speed_limit"] = limits_.speed;
    return info;
  }

  // The model message with the leading modes that fit --basis-message bytes, and the others in
  // basis messages of about that size. A newcomer's first frame then follows a message of rest,
  // mean and a few modes instead of the whole basis (paper size: tens of MB); it draws with the
  // modes it has, and the rest follow at the pace its connection takes them.
  void encode_basis() {
    const BasisDecoders& b = *fields_.bases();
    const int K = b.u.K, n = modes_per_message(b.rest.size(), a_.basis_message_bytes);
    const int here = std::min(K, n);
    model_ = net::WsServer::binary_message(
        model_message(b, model_info(), here, stepper_->particle_rigid_frames()));
    for (int k = here; k < K; k += n)
      basis_.push_back(net::WsServer::binary_message(basis_message(b, k, std::min(n, K - k))));
  }

  // The next basis message to each client once its last one has been sent: frames go on between
  // them, so a slow connection delays a frame by one basis message at most. Not counted against
  // the queue's caps (as the model message): a client receives the basis once, in full.
  void send_basis() {
    for (auto it = basis_due_.begin(); it != basis_due_.end();) {
      if (!net_.is_open(it->first)) {
        it = basis_due_.erase(it);
        continue;
      }
      if (net_.uncapped_queued(it->first) == 0) net_.send(it->first, basis_[it->second++], true);
      it = it->second == basis_.size() ? basis_due_.erase(it) : std::next(it);
    }
  }

  // A client's command, queued for the next frame; what is wrong with it, else "".
  std::string receive(int id, const std::string& text) {
    if (++commands_this_frame_[id] > kMaxCommandsPerFrame)
      return "over " + std::to_string(kMaxCommandsPerFrame) + " commands in one frame";
    try {
      ServeCommand c = parse_command(text, stepper_->colliders().size());
      if (c.kind == ServeCommand::move) {
        const std::string far =
            collider_motion_problem(limits_, c.collider, c.position, Vec3::Zero(), Vec3::Zero());
        if (!far.empty()) return far;
      } else if (!reset_allowed(id)) {
        return "";  // ignored: this client reset the scene less than a second ago
      }
      pending_.push_back(std::move(c));
      return "";
    } catch (const Error& e) {
      return e.what();
    }
  }

  // One frame of the scene: the guarded ROM steps, or at the scene's end the restart or hold
  // --at-end asks for. A failure starts the scene again; both are said once and counted.
  void advance(long frame) {
    // The scene's end: a visitor sees it start again (or held) instead of a frozen pose.
    const bool at_end =
        a_.at_end != "continue" && stepper_->time() >= (frames_ - 0.5) * frame_time_;
    if (at_end) {
      if (a_.at_end == "loop") restart();
      return;
    }
    try {
      const long recovered = guard_->health().recoveries;
      guard_->advance_frame();  // a step that would diverge is redone (rom/step/step_guard.h)
      // Said once; the status line counts the others.
      if (guard_->health().recoveries > recovered && redone_ == 0)
        say("nsf serve: a step that would have diverged was redone in frame " +
            std::to_string(frame + 1) + " (" + guard_->health().last_recovery +
            "); later ones are counted in the status line");
      redone_ += uint64_t(guard_->health().recoveries - recovered);
      if (!guard_->health().training_note.empty() && !said_outside_) {
        say("nsf serve: the run left the model's training box in frame " +
            std::to_string(frame + 1) + " (" + guard_->health().training_note +
            "): the model may not hold what follows");
        said_outside_ = true;
      }
    } catch (const Error& e) {
      // Said once, with why; every failure is counted in the status and the last line.
      if (failures_++ == 0)
        std::cerr << "nsf serve: the reduced-order model failed at t = " << stepper_->time()
                  << " s (" << e.what()
                  << "); starting the scene again (and again whenever it fails: counted in the "
                     "status line)"
                  << std::endl;
      restart();
    }
  }

  std::string status(long frames, double stepping, double wall) const {
    char b[448];
    std::snprintf(
        b, sizeof b,
        "%.1f frames/s over %.1f s (the ROM alone: %.1f frames/s, %.1f steps/s), "
        "%llu messages dropped, %llu clients dropped, %llu resets (%llu more ignored), "
        "%llu restarts after the model failed, %llu steps redone",
        double(frames) / wall, wall, double(frames) / stepping,
        double(frames) * stepper_->steps_per_frame() / stepping,
        static_cast<unsigned long long>(net_.messages_dropped()),
        static_cast<unsigned long long>(net_.clients_dropped()),
        static_cast<unsigned long long>(resets_), static_cast<unsigned long long>(resets_ignored_),
        static_cast<unsigned long long>(failures_), static_cast<unsigned long long>(redone_));
    return b;
  }

  // A log line, unless -q.
  void say(const std::string& line) const {
    if (!a_.quiet) std::cerr << line << std::endl;
  }

  // The scene at its start, from the file as read when the server started.
  std::unique_ptr<LatentStepper> start_scene() {
    RomSetup s = rom_setup(fields_, "the model", file_, a_.mu, choices_);
    frames_ = s.scene.settings.frames;
    frame_time_ = s.scene.settings.substeps * s.scene.settings.dt;
    mu_ = s.mu;
    limits_ = collider_limits(s.scene.settings);
    return std::make_unique<LatentStepper>(fields_, std::move(s.scene), s.mu, s.options);
  }

  // Back to the scene's start. A failure (a mesh file the scene names, changed on disk) is said
  // and the scene goes on as it is: nothing a client does ends the server.
  void restart() {
    try {
      std::unique_ptr<LatentStepper> fresh = start_scene();
      guard_.reset();
      stepper_ = std::move(fresh);
      guard_ = std::make_unique<StepGuard>(*stepper_);
      moving_.clear();
      targets_.clear();
    } catch (const Error& e) {
      if (!restart_failed_)
        std::cerr << "nsf serve: could not start the scene again (" << e.what()
                  << "); it goes on from where it is" << std::endl;
      restart_failed_ = true;
    }
  }

  // A client's reset is applied at most once a second; more are ignored (said once per client),
  // so a client resetting every frame cannot make the server restart the scene every frame.
  bool reset_allowed(int id) {
    const double now = mono_now();
    ResetClock& r = reset_clock_[id];
    if (r.applied > 0 && now - r.applied < kResetInterval) {
      ++resets_ignored_;
      if (!r.warned)
        say("nsf serve: client " + std::to_string(id) +
            " resets more often than once a second; those resets are ignored");
      r.warned = true;
      return false;
    }
    r.applied = now;
    // Forget clients that have not reset for a while (they may have gone).
    for (auto it = reset_clock_.begin(); it != reset_clock_.end();)
      it = now - it->second.applied > 60 ? reset_clock_.erase(it) : std::next(it);
    return true;
  }

  Eigen::VectorXf coefficients() const {
    return fields_.bases()->deformation_coefficients(stepper_->latent());
  }

  RigidCollider* rigid(size_t i) const {
    return dynamic_cast<RigidCollider*>(stepper_->colliders()[i].get());
  }

  std::vector<StreamPose> poses() const {
    std::vector<StreamPose> out;
    for (size_t i = 0; i < stepper_->colliders().size(); ++i) {
      StreamPose p = stream_pose(Vec3::Zero(), Mat3::Identity());
      if (RigidCollider* c = rigid(i)) {
        c->set_time(stepper_->time());
        p = stream_pose(c->pose().center, c->pose().rotation);
      }
      out.push_back(p);
    }
    return out;
  }

  // The rigid frames' maps x = R y + o (rom.rigid_frames), as the page applies them.
  std::vector<StreamPose> rigid_poses() const {
    std::vector<StreamPose> out(size_t(stepper_->rigid_frames().frames));
    for (int f = 0; f < stepper_->rigid_frames().frames; ++f) {
      Mat3 R;
      Vec3 o;
      stepper_->rigid_frame_pose(f, R, o);
      out[size_t(f)] = stream_pose(o, R);
    }
    return out;
  }

  // The commands received since the last frame, merged: the resets into one restart (moves
  // before the last reset are dropped with the scene they were for), the moves of a collider into
  // its last. A moved collider takes its rotation at once and travels to its position at the
  // scene's speed limit at most: over the next frame when it can, else over as many as that takes
  // (its velocity is what the material feels); it stops the frame after it arrives.
  void apply_commands() {
    size_t first = 0;
    for (size_t k = 0; k < pending_.size(); ++k)
      if (pending_[k].kind == ServeCommand::reset) first = k + 1;
    if (first > 0) {
      ++resets_;
      restart();
    }
    std::map<size_t, const ServeCommand*> moves;
    for (size_t k = first; k < pending_.size(); ++k) moves[pending_[k].collider] = &pending_[k];
    const double t = stepper_->time();
    for (size_t i = 0; i < stepper_->colliders().size(); ++i) {
      RigidCollider* c = rigid(i);
      const auto m = moves.find(i);
      if (m != moves.end()) targets_[i] = m->second->position;
      const auto target = targets_.find(i);
      if (!c || (target == targets_.end() && !moving_[i])) continue;
      c->set_time(t);
      RigidPose p = c->pose();
      p.angular_velocity.setZero();
      p.velocity.setZero();
      if (m != moves.end() && m->second->rotation) p.rotation = *m->second->rotation;
      moving_[i] = target != targets_.end();
      if (moving_[i]) {
        const Vec3 way = target->second - p.center;
        p.velocity = way / frame_time_;
        if (p.velocity.norm() > limits_.speed) p.velocity *= limits_.speed / p.velocity.norm();
        if (way.norm() <= limits_.speed * frame_time_) targets_.erase(target);  // there this frame
      }
      c->drive(p, t);
    }
    pending_.clear();
  }

  struct ResetClock {
    double applied = 0;  // when its last reset was applied (the monotonic clock)
    bool warned = false;
  };

  const ServeArgs& a_;
  NeuralFields fields_;
  const SceneFile file_;
  RomSettingChoices choices_;
  net::WsServer net_;
  std::unique_ptr<LatentStepper> stepper_;
  std::unique_ptr<StepGuard> guard_;  // holds a reference to stepper_
  int frames_ = 0;
  double frame_time_ = 0, mu_ = 0;
  ColliderLimits limits_;
  net::Message model_, last_;
  std::vector<net::Message> basis_;  // the modes the model message leaves out, in order
  std::map<int, size_t> basis_due_;  // client → its next basis message
  std::vector<ServeCommand> pending_;
  std::map<size_t, bool> moving_;
  std::map<size_t, Vec3> targets_;  // where a client sent a collider that is not there yet
  // A client sending more commands than this between two frames is flooding: it is dropped.
  static constexpr int kMaxCommandsPerFrame = 64;
  static constexpr double kResetInterval = 1.0;  // seconds between a client's resets, at least
  std::map<int, int> commands_this_frame_;
  std::map<int, ResetClock> reset_clock_;
  uint64_t resets_ = 0, resets_ignored_ = 0, failures_ = 0, redone_ = 0;
  bool said_outside_ = false;    // the first step outside the training box was said
  bool restart_failed_ = false;  // said once
  size_t max_clients_ = 0;
};

}  // namespace

void add_serve_command(CLI::App& app) {
  auto a = std::make_shared<ServeArgs>();
  CLI::App* cmd = app.add_subcommand(
      "serve",
      "Run the reduced-order model and stream its latent over WebSocket, with a page that "
      "draws it (docs/SERVE.md)");
  cmd->add_option("model", a->model, "Model file (nsf train; per-point bases)")->required();
  cmd->add_option("scene", a->scene, "Scene JSON (the model's scene)")->required();
  auto* mu =
      cmd->add_option("--mu", a->mu, "The scene's sweep parameter")->check(in_range(-1e300, 1e300));
  (void)mu;
  cmd->add_option("--set", a->overrides, "Override a scene value, e.g. --set material.E=5")
      ->type_name("KEY=VALUE")
      ->check(override_syntax());
  cmd->add_option("--samples,-k", a->samples, "Sample particles |S| (default: the scene's)")
      ->check(in_range(1, 100000000));
  cmd->add_option("--bind", a->net.bind,
                  "Address to listen on (0.0.0.0: every interface; anyone who can reach it may "
                  "watch and move colliders)")
      ->capture_default_str();
  cmd->add_option("--port,-p", a->net.port, "Port (0: any free one; the address is printed)")
      ->capture_default_str()
      ->check(in_range(0, 65535));
  cmd->add_option("--fps", a->fps,
                  "Frames per second to stream (default: real time, 1 / the scene's frame time; "
                  "0: as fast as the model steps)")
      ->check(in_range(0.0, 10000.0));
  cmd->add_option("--at-end", a->at_end,
                  "At the scene's last frame: loop (start it again), hold (stream its last pose) "
                  "or continue (step on past it)")
      ->capture_default_str()
      ->check(CLI::IsMember({"loop", "hold", "continue"}));
  cmd->add_option("--frames", a->frames, "Stop after this many frames (0: run until killed)")
      ->capture_default_str()
      ->check(in_range(0L, 1000000000L));
  cmd->add_option("--basis-message", a->basis_message_bytes,
                  "Bytes of the deformation basis per message: the model message carries the "
                  "leading modes that fit, the others follow between frames")
      ->capture_default_str()
      ->check(in_range<size_t>(1, size_t(1) << 30));
  cmd->add_option("--max-message", a->net.max_message,
                  "Largest message a client may send, bytes (larger: the client is dropped)")
      ->capture_default_str()
      ->check(in_range<size_t>(64, 1 << 20));
  cmd->add_option("--queue", a->net.max_queue,
                  "Messages waiting for one client; a client this far behind loses frames")
      ->capture_default_str()
      ->check(in_range<size_t>(2, 100000));
  cmd->add_option("--max-clients", a->net.max_clients,
                  "Open connections at most (lowered to what ulimit -n leaves free)")
      ->capture_default_str()
      ->check(in_range<size_t>(1, 10000));
  cmd->add_option("--allow-origin", a->net.allow_origins,
                  "Also open WebSockets for pages from this origin (e.g. http://example.org:8000; "
                  "'*': any page on any site may drive the server). Default: the server's own page")
      ->type_name("ORIGIN");
  cmd->add_option("--allow-host", a->net.allow_hosts,
                  "Also answer requests to this host name (any port; '*': any), e.g. the "
                  "machine's DNS name. Default: the bound address (loopback: localhost, 127.0.0.1, "
                  "[::1]; 0.0.0.0: localhost and any IP address) with the server's port")
      ->type_name("HOST");
  add_threads_option(cmd, a->threads, "Threads of the model");
  add_quiet_flag(cmd, a->quiet,
                 "Only the address, errors (each once) and the last line: no log lines about "
                 "clients, no status every 10 s");
  cmd->callback([a] {
    set_threads(a->threads);
    set_nn_threads(a->threads);
    Server server(*a);
    std::cout << "nsf serve: http://" << a->net.bind << ":" << server.port()
              << "/ (the page), ws://" << a->net.bind << ":" << server.port() << "/stream"
              << std::endl;
    server.run();
  });
}

}  // namespace nsf::app
