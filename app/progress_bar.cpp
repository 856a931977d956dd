#include "app/progress_bar.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <sstream>

#include <unistd.h>

namespace lacet::app {
namespace {

constexpr int kBarCells = 20;

double steadySeconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// 0:07, 12:34, 1:02:03 (whole seconds, rounded up: an ETA of 0:00 means done).
std::string clockTime(double seconds) {
    const auto s = static_cast<long long>(std::ceil(std::max(seconds, 0.0)));
    std::ostringstream os;
    if (s >= 3600) os << s / 3600 << ':' << std::setw(2) << std::setfill('0') << s / 60 % 60;
    else os << s / 60;
    os << ':' << std::setw(2) << std::setfill('0') << s % 60;
    return os.str();
}

// 2.3 s under a minute, then as a clock.
std::string duration(double seconds) {
    if (seconds >= 60.0) return clockTime(seconds);
    std::ostringstream os;
    os << std::fixed << std::setprecision(1) << seconds << " s";
    return os.str();
}

// 536/s; one decimal under 10 a second, where whole units would hide the rate.
std::string rate(double perSecond) {
    std::ostringstream os;
    os << std::fixed << std::setprecision(perSecond < 10.0 ? 1 : 0) << perSecond << "/s";
    return os.str();
}

}  // namespace

TerminalProgress::TerminalProgress() : TerminalProgress(std::cerr, ::isatty(STDERR_FILENO) == 1, steadySeconds) {}

TerminalProgress::TerminalProgress(std::ostream& out, bool terminal, Seconds now)
    : out_(out), terminal_(terminal), now_(std::move(now)) {}

TerminalProgress::~TerminalProgress() { end(); }

void TerminalProgress::begin(const std::string& stage, std::size_t total, const std::string& unit) {
    end();
    stage_ = stage;
    unit_ = unit;
    total_ = total;
    start_ = now_();
    done_.store(0);
    nextDraw_.store(start_ + (terminal_ ? kTerminalDelay : kPlainInterval));
    open_ = true;
}

void TerminalProgress::advance(std::size_t units) {
    done_.fetch_add(units, std::memory_order_relaxed);
    const double now = now_();
    if (now < nextDraw_.load(std::memory_order_relaxed)) return;
    const std::unique_lock lock(drawing_, std::try_to_lock);
    if (!lock.owns_lock() || !open_ || now < nextDraw_.load()) return;  // another thread is drawing, or just drew
    nextDraw_.store(now + (terminal_ ? kTerminalInterval : kPlainInterval));
    draw(now);
}

void TerminalProgress::end() {
    if (!open_) return;
    const std::lock_guard lock(drawing_);
    const double now = now_();
    if (!terminal_) {
        out_ << line(now, true) << '\n' << std::flush;
    } else if (now - start_ > kTerminalDelay || barWidth_ > 0) {
        const std::string text = line(now, true);
        out_ << '\r' << text << std::string(barWidth_ > text.size() ? barWidth_ - text.size() : 0, ' ') << '\n' << std::flush;
        barWidth_ = 0;
    }
    open_ = false;
}

std::string TerminalProgress::line(double now, bool final) const {
    const double elapsed = std::max(now - start_, 0.0);
    const std::size_t done = done_.load();
    const double perSecond = elapsed > 0.0 ? double(done) / elapsed : 0.0;
    std::ostringstream os;
    os << '[' << stage_ << "] ";
    const bool known = total_ > 0;
    if (final) {
        os << done;
        if (known && done != total_) os << '/' << total_;  // ended early: say how far it got
        os << ' ' << unit_ << " in " << duration(elapsed) << " (" << rate(perSecond) << ')';
        return os.str();
    }
    const double fraction = known ? std::min(double(done) / double(total_), 1.0) : 0.0;
    if (known && terminal_) {
        const int filled = static_cast<int>(fraction * kBarCells);
        os << '[' << std::string(std::size_t(filled), '#') << std::string(std::size_t(kBarCells - filled), '.') << "] ";
    }
    os << done;
    if (known) os << '/' << total_;
    os << ' ' << unit_;
    if (known) os << ' ' << static_cast<int>(fraction * 100.0) << '%';
    os << ' ' << rate(perSecond);
    if (known && perSecond > 0.0) os << " ETA " << clockTime(double(total_ - std::min(done, total_)) / perSecond);
    return os.str();
}

void TerminalProgress::draw(double now) {
    const std::string text = line(now, false);
    if (terminal_) {
        out_ << '\r' << text << std::string(barWidth_ > text.size() ? barWidth_ - text.size() : 0, ' ') << std::flush;
        barWidth_ = text.size();
    } else {
        out_ << text << '\n' << std::flush;
    }
}

}  // namespace lacet::app
