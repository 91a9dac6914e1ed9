// `nsf upgrade` on a model file of the basis model fixture (basis_model_fixture.h) saved as nsf
// saved it before it stored the run-time record.
#include <gtest/gtest.h>

#include <string>

#include "basis_model_fixture.h"
#include "cli_runner.h"
#include "error_matchers.h"
#include "nn/checked_archive.h"
#include "nn/model/neural_model.h"
#include "nn/neural_fields.h"
#include "nn_fixtures.h"

#include <torch/torch.h>

using nsf::NeuralFields;
using nsf::test::bit_identical;
using nsf::testing::basis::BasisModel;
using nsf::testing::basis::outputs;

// `nsf upgrade` gives a model file saved before nsf stored the record (the torch archive alone)
// the record, and the runtime then reads the same fields.
TEST_F(BasisModel, UpgradeAddsTheRecordToAnOlderFile) {
  const std::string old = (root_ / "old.nsf").string();
  {
    torch::serialize::OutputArchive a;
    nsf::NeuralModel::load(model()).write(a);
    nsf::save_checked_archive(a, old, "model file");
  }
  nsf::testing::expect_contains(nsf::testing::error_of([&] { NeuralFields::load_basis(old); }),
                                "no run-time record");
  const nsf::testing::CliResult r = nsf::testing::run_cli("upgrade " + old);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  nsf::testing::expect_contains(r.output, "with its run-time record");
  EXPECT_TRUE(bit_identical(outputs(model(), data(), true), outputs(old, data(), true)));
}
