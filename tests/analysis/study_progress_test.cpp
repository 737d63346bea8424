// The study's estimate of the time it has left, against the arithmetic by hand.
#include <gtest/gtest.h>

#include "analysis/batch/study_progress.h"

namespace ishibashi {
namespace {

JobProgress job(bool is_run, JobProgress::State state, double fraction, double elapsed_s) {
  return {"job", is_run, state, fraction, elapsed_s};
}

TEST(StudyProgress, TimeLeftProjectsRunningRunsAndAveragesPendingJobsOfTheirKind) {
  // One run done in 600 s; one at 25 % after 100 s (400 s in all, 300 left); two runs
  // pending at the mean of 600 and 400 = 500 s each; one analysis done in 60 s, one pending.
  const std::vector<JobProgress> jobs = {
      job(true, JobProgress::done, 1, 600), job(true, JobProgress::running, 0.25, 100), job(true, JobProgress::pending, 0, 0),
      job(true, JobProgress::pending, 0, 0), job(false, JobProgress::done, 0, 60), job(false, JobProgress::pending, 0, 0)};
  // Work left 300 + 500 + 500 + 60 = 1360 s; on two workers 680 s (longer than any one job).
  EXPECT_DOUBLE_EQ(estimate_time_left(jobs, 2).seconds, 680);
  EXPECT_DOUBLE_EQ(estimate_time_left(jobs, 1).seconds, 1360);
  EXPECT_EQ(estimate_time_left(jobs, 1).not_counted, 0);
  // On eight workers the longest single job (500 s) bounds it, not 1360 / 8.
  EXPECT_DOUBLE_EQ(estimate_time_left(jobs, 8).seconds, 500);
}

TEST(StudyProgress, SkippedJobsCountNothingAndUnknownKindsSaySo) {
  std::vector<JobProgress> jobs = {job(true, JobProgress::skipped, 0, 0), job(true, JobProgress::running, 0.5, 200)};
  EXPECT_DOUBLE_EQ(estimate_time_left(jobs, 2).seconds, 200);
  // Early in a run (under 5 % of its shaking) there is nothing to go by.
  jobs[1].fraction = 0.01;
  EXPECT_EQ(estimate_time_left(jobs, 2).not_counted, 1);
  // Pending analyses with none done yet are left out, and counted as such.
  jobs = {job(true, JobProgress::running, 0.5, 200), job(false, JobProgress::pending, 0, 0),
          job(false, JobProgress::pending, 0, 0)};
  EXPECT_DOUBLE_EQ(estimate_time_left(jobs, 1).seconds, 200);
  EXPECT_EQ(estimate_time_left(jobs, 1).not_counted, 2);
  // Everything done: nothing left.
  jobs = {job(true, JobProgress::done, 1, 200), job(false, JobProgress::skipped, 0, 0)};
  EXPECT_DOUBLE_EQ(estimate_time_left(jobs, 2).seconds, 0);
  EXPECT_EQ(estimate_time_left(jobs, 2).not_counted, 0);
}

TEST(StudyProgress, ARunThatGoesOnFromACheckpointIsTimedFromItsFirstReport) {
  // Resumed at 50 % of its shaking; its first report came 30 s after it started (loading
  // the checkpoint, the first frame). At 75 % after 130 s: 25 % in 100 s, so 100 s left
  // (timed from its start as a fresh run it would seem to need 130 / 0.75 - 130 = 43 s).
  JobProgress resumed = job(true, JobProgress::running, 0.75, 130);
  resumed.origin_fraction = 0.5;
  resumed.origin_s = 30;
  EXPECT_DOUBLE_EQ(estimate_time_left({resumed}, 1).seconds, 100);
  // Its pace stands for a whole run (400 s) for the runs not started yet; done, the same.
  std::vector<JobProgress> jobs = {resumed, job(true, JobProgress::pending, 0, 0)};
  EXPECT_DOUBLE_EQ(estimate_time_left(jobs, 1).seconds, 500);
  jobs[0].state = JobProgress::done;
  jobs[0].elapsed_s = 230;
  EXPECT_DOUBLE_EQ(estimate_time_left(jobs, 1).seconds, 400);

  // Through StudyProgress: the origin is the first report after a resumed start.
  std::vector<std::string> lines;
  StudyProgress p({{"run a", true}}, 1, 0.0, [&](const std::string& l) { lines.push_back(l); });
  p.started(0, /*resumed=*/true);
  p.advanced(0, 0.66);  // the first report: the origin; no pace yet
  p.advanced(0, 0.67);
  EXPECT_NE(lines.back().find("time left not known yet"), std::string::npos) << lines.back();
}

TEST(StudyProgress, DurationsReadAsAPersonWouldSayThem) {
  EXPECT_EQ(duration_text(40), "40 s");
  EXPECT_EQ(duration_text(12 * 60 + 10), "12 min");
  EXPECT_EQ(duration_text(3600 + 5 * 60 + 20), "1 h 05 min");
}

TEST(StudyProgress, PrintsWhichJobsRunAndHowFar) {
  std::vector<std::string> lines;
  StudyProgress p({{"run a", true}, {"run b", true}}, 2, 0.0, [&](const std::string& l) { lines.push_back(l); });
  p.started(0);
  p.started(1);
  p.advanced(0, 0.5);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_NE(lines[0].find("0 of 2 jobs done"), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("run a 50 % of its shaking"), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("run b 0 %"), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("; about "), std::string::npos) << lines[0];  // b, under 5 %, taken as long as a
  p.finished(0, JobProgress::done);
  EXPECT_NE(lines.back().find("1 of 2 jobs done"), std::string::npos) << lines.back();
  p.finished(1, JobProgress::failed);  // interrupted: not done, and nothing left to run
  EXPECT_NE(lines.back().find("1 of 2 jobs done, 1 failed"), std::string::npos) << lines.back();
  EXPECT_EQ(lines.back().find("left"), std::string::npos) << lines.back();
}

}  // namespace
}  // namespace ishibashi
