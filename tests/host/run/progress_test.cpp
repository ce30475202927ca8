// The progress line, the stage table and MPI rank detection.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "host/run/process_rank.h"
#include "host/run/progress.h"
#include "host/run/stage_table.h"
#include "kernels/core/error.h"

namespace romp::run {
namespace {

TEST(ProgressBar, ShowsFramesTimesAndAnEtaFromTheFramesThisProcessRan) {
  const std::string line = ProgressBar::line(6, 2, 10, 0.3, 0.5, 8.0);
  EXPECT_NE(line.find(" 60% frame 6/10"), std::string::npos) << line;
  EXPECT_NE(line.find("t = 0.300/0.500 s"), std::string::npos) << line;
  // 4 frames took 8 s, 4 remain.
  EXPECT_NE(line.find("ETA 8.0 s"), std::string::npos) << line;
  EXPECT_NE(ProgressBar::line(2, 2, 10, 0.1, 0.5, 0.0).find("ETA ?"), std::string::npos);
}

TEST(StageTable, ListsSharesAndTotal) {
  const std::string table = stage_table({{"p2g", 3.0}, {"g2p", 1.0}});
  EXPECT_NE(table.find("p2g"), std::string::npos);
  EXPECT_NE(table.find("75.0%"), std::string::npos);
  EXPECT_NE(table.find("total"), std::string::npos);
}

TEST(StageTable, ColumnsStayAlignedForLongStageNames) {
  const std::string table = stage_table({{"p2g", 3.0}, {"neural_plasticity", 1.0}});
  // Every line's seconds column ends at the same place.
  std::vector<std::size_t> ends;
  for (std::size_t start = 0, end; (end = table.find('\n', start)) != std::string::npos; start = end + 1) {
    const std::string line = table.substr(start, end - start);
    const std::size_t dot = line.find('.');
    if (dot != std::string::npos) ends.push_back(dot);
  }
  ASSERT_EQ(ends.size(), 3u);
  EXPECT_EQ(ends[0], ends[1]);
  EXPECT_EQ(ends[1], ends[2]);
}

TEST(ProcessRank, ReadsOpenMpiAndPmiAndDefaultsToOneProcess) {
  EXPECT_EQ(detect_process_rank({}).size, 1);
  const ProcessRank ompi = detect_process_rank({{"OMPI_COMM_WORLD_RANK", "2"}, {"OMPI_COMM_WORLD_SIZE", "4"}});
  EXPECT_EQ(ompi.rank, 2);
  EXPECT_EQ(ompi.size, 4);
  EXPECT_EQ(ompi.launcher, "OpenMPI");
  EXPECT_EQ(detect_process_rank({{"PMI_RANK", "0"}, {"PMI_SIZE", "3"}}).size, 3);
  EXPECT_THROW(detect_process_rank({{"PMI_RANK", "3"}, {"PMI_SIZE", "3"}}), Error);
  EXPECT_THROW(detect_process_rank({{"PMI_RANK", "x"}, {"PMI_SIZE", "3"}}), Error);
}

}  // namespace
}  // namespace romp::run
