// MPI_COMM_WORLD for `mpirun -np N tricot identify …` (issue 15). Rank 0 runs LM; every evaluation of
// the objective is one round: rank 0 sends every rank the parameters (and whether a Jacobian is
// wanted), every rank simulates its tests (test t on rank t mod N), and rank 0 receives the others'
// rows of y and ∂y/∂J as they arrive. Each test's arithmetic is the one of a one-process run, so the
// answer is the same bit for bit. No rank spins while it waits (wait_for, send).
#include "tricot/mpi/world.hpp"

#include <mpi.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <new>
#include <thread>
#include <vector>

#include "tricot/core/error.hpp"

namespace tricot::mpi {

namespace {

constexpr int kReadyTag = 1;    // a rank's exit code (0 = ready) and, when it failed, its error
constexpr int kValuesTag = 2;   // a rank's test values of one round
constexpr int kCommandTag = 3;  // rank 0's command: stop, or evaluate with the parameters
enum Command : int { stop = 0, evaluate = 1 };

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// A rank's error, as rank 0 rethrows it: the rank's own one-line message and exit code.
class RankError final : public InputError {
 public:
  RankError(const std::string& line, int code) : InputError(Location{}, line), code_(code) {}
  ExitCode exit_code() const override { return static_cast<ExitCode>(code_); }

 private:
  int code_;
};

// The exception in flight as the CLI would show it: exit code and one line.
std::pair<int, std::string> describe(const std::exception_ptr& error) {
  try {
    std::rethrow_exception(error);
  } catch (const InputError& e) {
    return {static_cast<int>(e.exit_code()), e.what()};
  } catch (const std::filesystem::filesystem_error& e) {
    return {static_cast<int>(ExitCode::input_missing),
            format_error({e.path1().empty() ? "filesystem" : e.path1().string(), 0, ""}, e.code().message(), {}, {})};
  } catch (const std::bad_alloc&) {
    return {static_cast<int>(ExitCode::usage), format_error({"memory", 0, ""}, "out of memory", {}, {})};
  } catch (const std::exception& e) {
    return {static_cast<int>(ExitCode::usage), e.what()};
  } catch (...) {
    return {static_cast<int>(ExitCode::usage), "unknown error"};
  }
}

// The byte stream of one rank's reply: its compute time, then each of its tests.
class Writer {
 public:
  template <class T>
  void put(const T& v) {
    put_bytes(&v, sizeof(T));
  }
  void put_bytes(const void* p, size_t n) {
    const size_t at = bytes.size();
    bytes.resize(at + n);
    if (n > 0) std::memcpy(bytes.data() + at, p, n);
  }
  std::vector<char> bytes;
};

class Reader {
 public:
  explicit Reader(const std::vector<char>& b) : b_(b) {}
  template <class T>
  T get() {
    T v;
    get_bytes(&v, sizeof(T));
    return v;
  }
  void get_bytes(void* p, size_t n) {
    if (at_ + n > b_.size()) throw std::runtime_error("mpi: a rank's message is shorter than its contents");
    if (n > 0) std::memcpy(p, b_.data() + at_, n);
    at_ += n;
  }

 private:
  const std::vector<char>& b_;
  size_t at_ = 0;
};

void pack(const ident::TestValues& v, Writer& w) {
  w.put<std::int32_t>(v.ok ? 1 : 0);
  w.put<std::int64_t>(static_cast<std::int64_t>(v.message.size()));
  w.put_bytes(v.message.data(), v.message.size());
  w.put<std::int64_t>(v.y.size());
  w.put_bytes(v.y.data(), sizeof(double) * static_cast<size_t>(v.y.size()));
  w.put<std::int64_t>(v.dy_dJ.rows());
  w.put<std::int64_t>(v.dy_dJ.cols());
  w.put_bytes(v.dy_dJ.data(), sizeof(double) * static_cast<size_t>(v.dy_dJ.size()));
}

void unpack(Reader& r, ident::TestValues& v) {
  v.ok = r.get<std::int32_t>() != 0;
  v.message.resize(static_cast<size_t>(r.get<std::int64_t>()));
  r.get_bytes(v.message.data(), v.message.size());
  v.y.resize(r.get<std::int64_t>());
  r.get_bytes(v.y.data(), sizeof(double) * static_cast<size_t>(v.y.size()));
  const auto rows = r.get<std::int64_t>();
  const auto cols = r.get<std::int64_t>();
  v.dy_dJ.resize(rows, cols);
  r.get_bytes(v.dy_dJ.data(), sizeof(double) * static_cast<size_t>(v.dy_dJ.size()));
}

std::vector<int> tests_of(int rank, int size, int tests) {
  std::vector<int> mine;
  for (int t = rank; t < tests; t += size) mine.push_back(t);
  return mine;
}

// Waits for a message without spinning: Open MPI's blocking calls poll a core at 100 % while they
// wait, which on a machine running more ranks than cores (or a worker idle while rank 0 writes its
// outputs) takes the CPU from the ranks that compute. Polling with sleeps from 50 µs up to 2 ms adds
// at most ~2 ms to a round that takes a second. Returns the source.
int wait_for(int source, int tag, MPI_Status& status) {
  auto pause = std::chrono::microseconds(50);
  for (;;) {
    int arrived = 0;
    MPI_Iprobe(source, tag, MPI_COMM_WORLD, &arrived, &status);
    if (arrived) return status.MPI_SOURCE;
    std::this_thread::sleep_for(pause);
    pause = std::min(2 * pause, std::chrono::microseconds(2000));
  }
}

// Sends without spinning: a rank's reply (up to a megabyte here) goes by rendezvous, so a blocking
// send would poll a core until rank 0, still on its own tests, posts the receive.
void send(const void* data, int count, MPI_Datatype type, int dest, int tag) {
  MPI_Request request;
  MPI_Isend(data, count, type, dest, tag, MPI_COMM_WORLD, &request);
  auto pause = std::chrono::microseconds(50);
  for (;;) {
    int done = 0;
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done) return;
    std::this_thread::sleep_for(pause);
    pause = std::min(2 * pause, std::chrono::microseconds(2000));
  }
}

template <class T>
std::vector<T> receive(int source, int tag, MPI_Datatype type, int* from = nullptr) {
  MPI_Status status;
  const int sender = wait_for(source, tag, status);
  if (from) *from = sender;
  int count = 0;
  MPI_Get_count(&status, type, &count);
  std::vector<T> b(static_cast<size_t>(count));
  MPI_Recv(b.data(), count, type, sender, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return b;
}

void send_command(int size, Command command, bool jacobian, const Eigen::VectorXd& J) {
  std::vector<double> m{static_cast<double>(command), jacobian ? 1.0 : 0.0};
  m.insert(m.end(), J.data(), J.data() + J.size());
  for (int r = 1; r < size; ++r)
    MPI_Send(m.data(), static_cast<int>(m.size()), MPI_DOUBLE, r, kCommandTag, MPI_COMM_WORLD);
}

// Rank 0's side of the rounds: the objective's TestSplit.
class RankSplit final : public ident::TestSplit {
 public:
  explicit RankSplit(int size) : size_(size) {}

  std::vector<ident::TestValues> evaluate(
      const Eigen::VectorXd& J, bool jacobian, int tests,
      const std::function<std::vector<ident::TestValues>(const std::vector<int>&)>& local) const override {
    // One round at a time: LM's finite-difference columns and the stability test call evaluate()
    // from several threads, and the replies of two rounds must not be mixed.
    std::lock_guard<std::mutex> lock(mutex_);
    const auto round_start = Clock::now();
    send_command(size_, Command::evaluate, jacobian, J);
    const double send_seconds = seconds_since(round_start);

    // The replies are received even when the own share throws (out of memory): the other ranks
    // must not be left blocked in a send.
    std::vector<ident::TestValues> values;
    std::exception_ptr error;
    const auto local_start = Clock::now();
    try {
      values = local(tests_of(0, size_, tests));
    } catch (...) {
      error = std::current_exception();
      values.assign(tests, {});
    }
    const double local_seconds = seconds_since(local_start);

    double slowest = local_seconds, received = 0, largest = 0;
    const auto recv_start = Clock::now();
    for (int k = 1; k < size_; ++k) {  // in the order they arrive: each test has its own slot
      int r = 0;
      const std::vector<char> b = receive<char>(MPI_ANY_SOURCE, kValuesTag, MPI_BYTE, &r);
      received += static_cast<double>(b.size());
      largest = std::max(largest, static_cast<double>(b.size()));
      Reader reader(b);
      slowest = std::max(slowest, reader.get<double>());
      for (int t : tests_of(r, size_, tests)) unpack(reader, values[t]);
    }
    const double recv_seconds = seconds_since(recv_start);

    Traffic& s = traffic_;
    ++s.rounds;
    if (jacobian) ++s.jacobian_rounds;
    s.bytes_sent += static_cast<double>((size_ - 1) * sizeof(double) * (2 + J.size()));
    s.bytes_received += received;
    s.largest_message = std::max(s.largest_message, largest);
    s.mpi_seconds += send_seconds + recv_seconds;
    s.local_seconds += local_seconds;
    s.overhead_seconds += std::max(0.0, seconds_since(round_start) - slowest);
    if (error) std::rethrow_exception(error);
    return values;
  }

  Traffic traffic() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return traffic_;
  }

 private:
  int size_;
  mutable std::mutex mutex_;
  mutable Traffic traffic_;
};

// Rank 0 waits for every rank's ready message: the first failed rank's error, or none.
std::exception_ptr gather_ready(int size) {
  std::exception_ptr first;
  for (int r = 1; r < size; ++r) {
    const std::vector<char> b = receive<char>(r, kReadyTag, MPI_BYTE);
    Reader reader(b);
    const auto code = reader.get<std::int32_t>();
    if (code == 0 || first) continue;
    const std::string line(b.begin() + sizeof(std::int32_t), b.end());
    first = std::make_exception_ptr(RankError(line + " (on MPI rank " + std::to_string(r) + ")", code));
  }
  return first;
}

}  // namespace

struct World::Impl {
  bool initialized = false;
  bool ready = false;  // rank 0: the ready messages were gathered
  std::shared_ptr<RankSplit> split;
};

std::string Traffic::brief_report() const {
  char line[400];
  std::snprintf(
      line, sizeof line,
      "mpi: %d rounds (%d with the Jacobian), %.3g MB received (largest message %.3g kB), %.3g kB sent; "
      "rank 0: %.3g s in MPI calls (waits included), %.3g s on its own tests, %.3g s overhead beyond the slowest rank",
      rounds, jacobian_rounds, bytes_received / 1e6, largest_message / 1e3, bytes_sent / 1e3, mpi_seconds,
      local_seconds, overhead_seconds);
  return line;
}

World::World() : impl_(std::make_shared<Impl>()) {
  if (launcher_size() == 1) {  // not started by an MPI launcher: one process, no MPI
    refuse_duplicated_tasks(1);
    return;
  }
  int provided = 0;
  // Serialized: rank 0 calls MPI from whichever thread evaluates (one at a time, RankSplit's lock).
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided);
  impl_->initialized = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  if (provided < MPI_THREAD_SERIALIZED && size_ > 1) {
    if (rank_ == 0)
      std::fprintf(stderr, "tricot: error: %s\n",
                   format_error({"mpi", 0, ""}, "this MPI library cannot be called from several threads", "",
                                "MPI_THREAD_SERIALIZED")
                       .c_str());
    MPI_Abort(MPI_COMM_WORLD, static_cast<int>(ExitCode::usage));
  }
  if (size_ == 1 && slurm_step_tasks() > 1) {  // each task its own world of one (a PMI it does not speak)
    MPI_Finalize();
    impl_->initialized = false;
    refuse_duplicated_tasks(size_);
  }
}

World::~World() {
  if (!impl_->initialized) return;
  if (rank_ == 0 && size_ > 1) {
    if (!impl_->ready) gather_ready(size_);  // an error before lead(): the others still say ready
    send_command(size_, Command::stop, false, {});
  }
  MPI_Finalize();
}

void World::lead(ident::Objective& objective) {
  if (size_ == 1 || rank_ != 0) return;
  impl_->ready = true;
  if (const std::exception_ptr error = gather_ready(size_)) std::rethrow_exception(error);
  impl_->split = std::make_shared<RankSplit>(size_);
  objective.set_split(impl_->split);
}

Traffic World::traffic() const { return impl_->split ? impl_->split->traffic() : Traffic{}; }

void World::serve(const std::function<const ident::Objective*()>& build) {
  if (rank_ == 0) return;
  const ident::Objective* objective = nullptr;
  int code = 0;
  std::string message;
  try {
    objective = build();
  } catch (...) {
    std::tie(code, message) = describe(std::current_exception());
    if (code == 0) code = static_cast<int>(ExitCode::usage);
  }
  Writer ready;
  ready.put<std::int32_t>(code);
  ready.put_bytes(message.data(), message.size());
  send(ready.bytes.data(), static_cast<int>(ready.bytes.size()), MPI_BYTE, 0, kReadyTag);

  try {
    for (;;) {
      const std::vector<double> command = receive<double>(0, kCommandTag, MPI_DOUBLE);
      if (command.size() < 2 || static_cast<int>(command[0]) == Command::stop) return;
      if (!objective) throw std::logic_error("asked to evaluate without an objective");
      const Eigen::VectorXd J =
          Eigen::Map<const Eigen::VectorXd>(command.data() + 2, static_cast<Eigen::Index>(command.size() - 2));
      if (J.size() != static_cast<Eigen::Index>(objective->parameters().size()))
        throw std::logic_error("rank 0 sent " + std::to_string(J.size()) + " parameters");
      const bool jacobian = command[1] != 0;
      const auto start = Clock::now();
      const int T = static_cast<int>(objective->models().size());
      const std::vector<int> mine = tests_of(rank_, size_, T);
      const std::vector<ident::TestValues> values = objective->evaluate_tests(J, jacobian, mine);
      Writer w;
      w.put<double>(seconds_since(start));
      for (int t : mine) pack(values[t], w);
      send(w.bytes.data(), static_cast<int>(w.bytes.size()), MPI_BYTE, 0, kValuesTag);
    }
  } catch (...) {
    const auto [c, line] = describe(std::current_exception());
    std::fprintf(stderr, "tricot: error: %s (on MPI rank %d)\n", line.c_str(), rank_);
    MPI_Abort(MPI_COMM_WORLD, c == 0 ? static_cast<int>(ExitCode::usage) : c);
  }
}

}  // namespace tricot::mpi
