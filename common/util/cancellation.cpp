#include "util/cancellation.h"

#include <utility>

namespace gistream {
namespace {

thread_local std::stop_token t_token;

}  // namespace

std::stop_token CurrentStopToken() { return t_token; }

bool Cancelled() { return t_token.stop_requested(); }

CancellationScope::CancellationScope(std::stop_token token)
    : previous_(std::exchange(t_token, std::move(token))) {}

CancellationScope::~CancellationScope() { t_token = std::move(previous_); }

}  // namespace gistream
