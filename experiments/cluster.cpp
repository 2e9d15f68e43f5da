#include "experiments/cluster.h"
#include <tbb/info.h>
#include <algorithm>
#include <cstring>
#include <thread>
#include "core/error.h"

namespace lb {

namespace {
// The farm's messages. A worker's first Request says it is ready; after that
// each Result (or Failure) also asks for the next task.
enum FarmTag { Request = 1, Task = 2, Result = 3, Failure = 4, Stop = 5 };
}  // namespace

void Farm::distribute(const std::function<std::optional<std::string>(int)>& next,
                      const std::function<void(int, std::string&&)>& onResult) {
  for (;;) {
    bool drained = false;  // `next` had nothing (for now) for an idle worker
    while (!idle_.empty()) {
      std::optional<std::string> task = next(idle_.back());
      if (!task) {
        drained = true;
        break;
      }
      cluster_.send(idle_.back(), Task, *task);
      idle_.pop_back();
      ++busy_;
    }
    // Nothing out and nothing to hand out: done. (With no worker idle yet,
    // the first Requests are still to come.)
    if (busy_ == 0 && (drained || workers() == 0)) return;
    Message m = cluster_.receive(Cluster::AnySource);
    if (m.tag == Request) {
      idle_.push_back(m.source);
    } else if (m.tag == Result || m.tag == Failure) {
      --busy_;
      idle_.push_back(m.source);
      if (m.tag == Result) {
        onResult(m.source, std::move(m.bytes));
      } else {
        ByteReader r(m.bytes);
        int code = int(r.u64());
        throw RemoteFailure(code, r.str() + " (on rank " + std::to_string(m.source) + ")");
      }
    }
  }
}

bool Farm::stopWorkers(int code) {
  if (stopped_) return true;
  if (busy_ > 0) return false;
  // Every worker gets its Stop: an idle one at once; one that has not yet
  // asked receives it as the answer to its first Request.
  for (int w = 1; w < cluster_.size(); ++w) cluster_.send(w, Stop, ByteWriter().u64(uint64_t(code)).take());
  stopped_ = true;
  return true;
}

int Farm::serve(const std::function<std::string(const std::string&)>& work) {
  cluster_.send(0, Request, "");
  for (;;) {
    Message m = cluster_.receive(0);
    if (m.tag == Stop) return int(ByteReader(m.bytes).u64());
    if (m.tag != Task) continue;
    try {
      std::string result = work(m.bytes);
      cluster_.send(0, Result, result);
    } catch (const RemoteFailure& e) {
      cluster_.send(0, Failure, ByteWriter().u64(uint64_t(e.exitCode)).str(e.what()).take());
    } catch (const ConfigError& e) {
      cluster_.send(0, Failure, ByteWriter().u64(2).str(e.what()).take());
    } catch (const std::exception& e) {
      cluster_.send(0, Failure, ByteWriter().u64(1).str(e.what()).take());
    } catch (...) {
      cluster_.send(0, Failure, ByteWriter().u64(1).str("an unknown exception").take());
    }
  }
}

int workerThreads(int requested, const Cluster& cluster) {
  if (requested > 0) return requested;
  int share = int(std::thread::hardware_concurrency()) / std::max(1, cluster.workersOnThisNode());
  return std::max(1, std::min(tbb::info::default_concurrency(), share));
}

ByteWriter& ByteWriter::image(const Image& img) {
  u64(uint64_t(img.width)).u64(uint64_t(img.height));
  return raw(img.pixels.data(), img.pixels.size() * sizeof(Color));
}

void ByteReader::raw(void* p, size_t n) {
  if (bytes_.size() - at_ < n) throw std::runtime_error("a truncated message between ranks");
  std::memcpy(p, bytes_.data() + at_, n);
  at_ += n;
}

std::string ByteReader::str() {
  uint64_t n = u64();
  if (bytes_.size() - at_ < n) throw std::runtime_error("a truncated message between ranks");
  std::string s = bytes_.substr(at_, n);
  at_ += n;
  return s;
}

Image ByteReader::image() {
  int w = int(u64()), h = int(u64());
  Image img(w, h);
  raw(img.pixels.data(), img.pixels.size() * sizeof(Color));
  return img;
}

}  // namespace lb
