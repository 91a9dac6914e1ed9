// Several processes training together (nn/train/gradient_team.h): the entries of a global batch
// this process computes, the gradients and loss summed over the team each step, and process 0's
// setup sent to the others.
#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "nn/train/trainer_state.h"

namespace nsf::train {

torch::Tensor Trainer::entries(const torch::Tensor& t, const std::vector<int64_t>& rows) const {
  if (!team_) return t;  // a single process computes every entry
  return t.index_select(0, torch::tensor(rows, torch::kInt64).to(t.device()));
}

double Trainer::sum_over_team(double loss) {
  if (!team_) return loss;
  // Every parameter's gradient (zeros where this process computed no entry) and the loss, in
  // one buffer: one MPI_Allreduce per step.
  std::vector<torch::Tensor> grads;
  size_t count = 1;
  for (auto& group : adam_->param_groups())
    for (auto& p : group.params()) {
      if (!p.grad().defined()) p.mutable_grad() = torch::zeros_like(p);
      grads.push_back(p.grad());
      count += size_t(p.numel());
    }
  std::vector<float> flat(count);
  size_t at = 0;
  for (const torch::Tensor& g : grads) {
    const torch::Tensor c = g.to(torch::kCPU).contiguous();
    std::copy_n(c.data_ptr<float>(), c.numel(), flat.data() + at);
    at += size_t(c.numel());
  }
  flat[at] = float(loss);
  team_->sum(flat.data(), flat.size());
  at = 0;
  for (torch::Tensor& g : grads) {
    g.copy_(torch::from_blob(flat.data() + at, g.sizes()));
    at += size_t(g.numel());
  }
  return double(flat[at]);
}

void Trainer::share_setup() {
  if (!team_) return;
  std::string bytes;
  if (team_rank() == 0) {
    torch::serialize::OutputArchive a, m;
    model_.write(m);
    a.write("model", m);
    for (int f = 0; f < kStageCount; ++f)
      if (targets_[f].defined()) a.write("basis_targets_" + std::to_string(f), targets_[f], true);
    std::ostringstream os;
    a.save_to(os);
    bytes = os.str();
  }
  team_->broadcast(bytes);
  if (team_rank() == 0) return;
  std::istringstream is(bytes);
  torch::serialize::InputArchive a, m;
  a.load_from(is);
  a.read("model", m);
  model_ = NeuralModel::read(m, "the model of process 0");
  for (int f = 0; f < kStageCount; ++f)
    a.try_read("basis_targets_" + std::to_string(f), targets_[f], true);
}

}  // namespace nsf::train
