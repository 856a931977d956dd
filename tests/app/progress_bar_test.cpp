// The terminal progress bar and its plain-line mode, driven by a fake clock into a string: what it
// prints and when (the 1 s delay, at most 10 redraws a second, a line every 10 s in a log), the
// rate and ETA, and exact counts under concurrent advance().
#include <atomic>
#include <sstream>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "app/progress_bar.h"

namespace lacet::app {
namespace {

// A progress bar on a string stream, timed by a clock the test sets (seconds).
struct Fixture {
    explicit Fixture(bool terminal) : progress(out, terminal, [this] { return now; }) {}
    // What was printed since the last call.
    std::string printed() {
        std::string s = out.str();
        out.str("");
        return s;
    }
    double now = 0.0;
    std::ostringstream out;
    TerminalProgress progress;
};

TEST(ProgressBar, TerminalStageUnderOneSecondPrintsNothing) {
    Fixture f(true);
    f.progress.begin("clipping", 100, "quads");
    f.now = 0.5;
    f.progress.advance(60);
    f.now = 0.9;
    f.progress.advance(40);
    f.progress.end();
    EXPECT_EQ(f.printed(), "");
}

TEST(ProgressBar, TerminalBarShowsRateAndEtaAfterOneSecond) {
    Fixture f(true);
    f.progress.begin("producing tiles", 100, "tiles");
    f.now = 0.8;
    f.progress.advance(10);
    EXPECT_EQ(f.printed(), "");  // not yet a second
    f.now = 2.0;
    f.progress.advance(40);
    EXPECT_EQ(f.printed(), "\r[producing tiles] [##########..........] 50/100 tiles 50% 25/s ETA 0:02");
}

TEST(ProgressBar, TerminalRedrawsAtMostTenTimesASecond) {
    Fixture f(true);
    f.progress.begin("producing tiles", 1000, "tiles");
    f.now = 1.5;
    f.progress.advance(300);
    EXPECT_NE(f.printed(), "");
    f.now = 1.55;
    f.progress.advance(1);
    EXPECT_EQ(f.printed(), "");  // 0.05 s after the last redraw
    f.now = 1.65;
    f.progress.advance(1);
    EXPECT_EQ(f.printed(), "\r[producing tiles] [######..............] 302/1000 tiles 30% 183/s ETA 0:04");
}

TEST(ProgressBar, TerminalEndReplacesTheBarWithTheFinalLine) {
    Fixture f(true);
    f.progress.begin("producing tiles", 100, "tiles");
    f.now = 2.0;
    f.progress.advance(50);
    EXPECT_EQ(f.printed(), "\r[producing tiles] [##########..........] 50/100 tiles 50% 25/s ETA 0:02");
    f.now = 4.0;
    f.progress.advance(50);
    const std::string bar = f.printed();
    EXPECT_EQ(bar, "\r[producing tiles] [####################] 100/100 tiles 100% 25/s ETA 0:00");
    f.progress.end();
    const std::string final = "[producing tiles] 100 tiles in 4.0 s (25/s)";
    // The bar's line is overwritten and cleared to its end, then the line is kept.
    EXPECT_EQ(f.printed(), "\r" + final + std::string(bar.size() - 1 - final.size(), ' ') + "\n");
}

TEST(ProgressBar, TerminalStageThatRanLongPrintsItsEndEvenWithoutABar) {
    Fixture f(true);
    f.progress.begin("saving", 1, "files");
    f.now = 2.5;
    f.progress.end();  // ended without a single advance: stopped early
    EXPECT_EQ(f.printed(), "\r[saving] 0/1 files in 2.5 s (0.0/s)\n");
}

TEST(ProgressBar, UnknownTotalShowsCountAndRateWithoutEta) {
    Fixture f(true);
    f.progress.begin("reading", 0, "features");
    f.now = 2.0;
    f.progress.advance(300);
    EXPECT_EQ(f.printed(), "\r[reading] 300 features 150/s");
    f.now = 3.0;
    f.progress.end();
    EXPECT_EQ(f.printed(), "\r[reading] 300 features in 3.0 s (100/s)\n");
}

TEST(ProgressBar, PlainLinesEveryTenSecondsAndAtTheEnd) {
    Fixture f(false);
    f.progress.begin("fitting splines", 100, "curves");
    f.now = 5.0;
    f.progress.advance(10);
    EXPECT_EQ(f.printed(), "");
    f.now = 10.0;
    f.progress.advance(10);
    EXPECT_EQ(f.printed(), "[fitting splines] 20/100 curves 20% 2.0/s ETA 0:40\n");
    f.now = 19.0;
    f.progress.advance(30);
    EXPECT_EQ(f.printed(), "");
    f.now = 20.0;
    f.progress.advance(50);
    EXPECT_EQ(f.printed(), "[fitting splines] 100/100 curves 100% 5.0/s ETA 0:00\n");
    f.now = 23.0;
    f.progress.end();
    EXPECT_EQ(f.printed(), "[fitting splines] 100 curves in 23.0 s (4.3/s)\n");
}

TEST(ProgressBar, PlainQuickStagePrintsOnlyItsEnd) {
    Fixture f(false);
    f.progress.begin("fitting splines", 1234, "curves");
    f.now = 2.3;
    f.progress.advance(1234);
    f.progress.end();
    EXPECT_EQ(f.printed(), "[fitting splines] 1234 curves in 2.3 s (537/s)\n");
}

TEST(ProgressBar, LongEtaAsHoursMinutesSeconds) {
    Fixture f(false);
    f.progress.begin("producing tiles", 1000, "tiles");
    f.now = 16.0;
    f.progress.advance(1);
    EXPECT_EQ(f.printed(), "[producing tiles] 1/1000 tiles 0% 0.1/s ETA 4:26:24\n");
    f.now = 75.0;
    f.progress.end();
    EXPECT_EQ(f.printed(), "[producing tiles] 1/1000 tiles in 1:15 (0.0/s)\n");
}

TEST(ProgressBar, BeginEndsThePreviousStageAndTheDestructorTheLast) {
    std::ostringstream out;
    double now = 0.0;
    {
        TerminalProgress p(out, false, [&now] { return now; });
        p.begin("a", 2, "items");
        p.advance(2);
        now = 1.0;
        p.begin("b", 0, "rows");
        p.advance(5);
        now = 2.0;
    }
    EXPECT_EQ(out.str(), "[a] 2 items in 1.0 s (2.0/s)\n[b] 5 rows in 1.0 s (5.0/s)\n");
}

TEST(ProgressBar, ConcurrentAdvanceCountsEveryUnit) {
    // Every call of the clock moves it 1 ms on, so the threads keep finding a redraw due and
    // contend for drawing.
    std::atomic<long> ticks{0};
    std::ostringstream out;
    TerminalProgress p(out, true, [&ticks] { return double(ticks.fetch_add(1)) * 1e-3; });
    constexpr std::size_t kThreads = 8, kPerThread = 20000;
    p.begin("producing tiles", kThreads * kPerThread, "tiles");
    std::vector<std::thread> threads;
    for (std::size_t t = 0; t < kThreads; ++t)
        threads.emplace_back([&p] {
            for (std::size_t i = 0; i < kPerThread; ++i) p.advance();
        });
    for (std::thread& t : threads) t.join();
    p.end();
    const std::string text = out.str();
    const std::size_t last = text.rfind('\r');
    ASSERT_NE(last, std::string::npos);
    EXPECT_EQ(text.substr(last + 1, text.find(" in ", last) - last - 1), "[producing tiles] 160000 tiles");
    EXPECT_EQ(text.back(), '\n');
    // Redraws: one per 0.1 s of the clock at most.
    const auto redraws = std::count(text.begin(), text.end(), '\r');
    EXPECT_LE(double(redraws), double(ticks.load()) * 1e-3 / TerminalProgress::kTerminalInterval + 2.0);
}

TEST(ProgressBar, NullProgressIsAllowed) {
    Progress* none = nullptr;
    progressBegin(none, "stage", 1, "units");
    progressAdvance(none);
    progressEnd(none);
}

}  // namespace
}  // namespace lacet::app
