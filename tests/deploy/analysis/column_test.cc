// srics column: the largest value of a run folder's CSV column by name, over the rows that
// match; what the scripts that watch a run read instead of splitting the files themselves.

#include "deploy/analysis/column.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace srics::analysis {
namespace {

class ColumnTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::path(::testing::TempDir()) / "srics_column_test";
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    // nodes.csv's first columns as the monitor writes them, a quoted host with a comma
    std::ofstream(dir_ / "nodes.csv") << "wall_time,run_id,role,node_id,host,pid,state,policy_version,env_steps\n"
                                         "1.0,r,actor,0,\"a,b\",10,exploring,2,150\n"
                                         "2.0,r,actor,1,b,11,exploring,3,900\n"
                                         "3.0,r,learner,0,a,12,training,5,\n"
                                         "4.0,r,actor,0,\"a,b\",10,exploring,4,1200\n"
                                         "5.0,r,actor,0,\"a,b\",10,stopping,1,80\n";
  }
  ColumnOptions Options(std::string column, std::vector<std::string> where = {}) {
    return {dir_ / "nodes.csv", std::move(column), std::move(where)};
  }
  std::filesystem::path dir_;
};

TEST_F(ColumnTest, LargestValueOverTheMatchingRows) {
  EXPECT_EQ(ColumnMax(Options("env_steps")), 1200);  // the learner's empty field is no number
  EXPECT_EQ(ColumnMax(Options("env_steps", {"role=actor", "node_id=1"})), 900);
  EXPECT_EQ(ColumnMax(Options("policy_version", {"role=actor", "node_id=0"})), 4);
  EXPECT_EQ(ColumnMax(Options("policy_version", {"host=a,b"})), 4);  // a quoted field, whole
  EXPECT_EQ(ColumnMax(Options("env_steps", {"role=learner"})), std::nullopt);
  EXPECT_EQ(ColumnMax(Options("env_steps", {"role=graph"})), std::nullopt);
  EXPECT_EQ(Column(Options("env_steps", {"role=graph"})), 0);  // prints 0: not there yet
}

TEST_F(ColumnTest, WhatIsWrongIsNamed) {
  auto message = [&](ColumnOptions options) {
    try {
      ColumnMax(options);
      return std::string("accepted");
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
  };
  EXPECT_NE(message(Options("steps")).find("no column 'steps'"), std::string::npos);
  EXPECT_NE(message(Options("env_steps", {"rank=1"})).find("no column 'rank'"), std::string::npos);
  EXPECT_NE(message(Options("env_steps", {"role"})).find("--where role: expected NAME=VALUE"), std::string::npos);
  EXPECT_NE(message({dir_ / "missing.csv", "env_steps", {}}).find("missing.csv: no such file"), std::string::npos);
  EXPECT_EQ(Column({dir_ / "missing.csv", "env_steps", {}}), 1);
}

}  // namespace
}  // namespace srics::analysis
