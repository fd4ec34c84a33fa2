// The suite's bounded random-input test for one fuzz target: runs LLVMFuzzerTestOneInput on
// every seed file of the corpus, on mutations of the seeds (bit flips, byte changes, cuts,
// insertions, splices) and on random byte strings, all from a fixed seed so a failure
// reproduces. A crash or sanitizer report fails the test; on a fatal signal the input being run
// is written to ./fuzz-random-crash-input so it can be replayed with the libFuzzer binary.
//
//   porter-fuzz-random-NAME --runs N --max-len L [--corpus DIR] [--seed S]

#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

using Bytes = std::vector<std::uint8_t>;

Bytes mutate(const Bytes& seed, const std::vector<Bytes>& corpus, std::mt19937_64& rng,
             std::size_t max_len) {
  Bytes out = seed;
  const int edits = 1 + static_cast<int>(rng() % 4);
  for (int e = 0; e < edits; ++e) {
    switch (rng() % 6) {
      case 0:  // flip a bit
        if (!out.empty()) out[rng() % out.size()] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
        break;
      case 1:  // set a byte to an interesting value
        if (!out.empty()) {
          static const std::uint8_t values[] = {0x00, 0x01, 0x7F, 0x80, 0xFF, 0xFE, 0x20, 0x0D};
          out[rng() % out.size()] = values[rng() % sizeof values];
        }
        break;
      case 2:  // truncate
        if (!out.empty()) out.resize(rng() % out.size());
        break;
      case 3:  // insert random bytes
        if (out.size() < max_len) {
          const std::size_t at = out.empty() ? 0 : rng() % (out.size() + 1);
          const std::size_t n = 1 + rng() % 8;
          for (std::size_t i = 0; i < n; ++i) out.insert(out.begin() + at, static_cast<std::uint8_t>(rng()));
        }
        break;
      case 4:  // overwrite four bytes (a length or count field)
        if (out.size() >= 4) {
          const std::size_t at = rng() % (out.size() - 3);
          const std::uint32_t v = static_cast<std::uint32_t>(rng());
          std::memcpy(out.data() + at, &v, 4);
        }
        break;
      case 5:  // splice with another seed
        if (!corpus.empty()) {
          const Bytes& other = corpus[rng() % corpus.size()];
          const std::size_t cut = out.empty() ? 0 : rng() % out.size();
          out.resize(cut);
          const std::size_t from = other.empty() ? 0 : rng() % other.size();
          out.insert(out.end(), other.begin() + static_cast<std::ptrdiff_t>(from), other.end());
        }
        break;
    }
  }
  if (out.size() > max_len) out.resize(max_len);
  return out;
}

const Bytes* g_current = nullptr;

extern "C" void save_input_and_die(int signo) {
  if (g_current != nullptr) {
    const int fd = ::open("fuzz-random-crash-input", O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      [[maybe_unused]] const ssize_t n = ::write(fd, g_current->data(), g_current->size());
      ::close(fd);
    }
  }
  std::signal(signo, SIG_DFL);
  std::raise(signo);
}

void run(const Bytes& input) {
  g_current = &input;
  LLVMFuzzerTestOneInput(input.data(), input.size());
  g_current = nullptr;
}

}  // namespace

int main(int argc, char** argv) {
  long runs = 20000;
  std::size_t max_len = 4096;
  std::uint64_t seed = 1;
  std::string corpus_dir;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i];
    if (key == "--runs") runs = std::atol(argv[i + 1]);
    else if (key == "--max-len") max_len = static_cast<std::size_t>(std::atol(argv[i + 1]));
    else if (key == "--seed") seed = std::strtoull(argv[i + 1], nullptr, 10);
    else if (key == "--corpus") corpus_dir = argv[i + 1];
    else {
      std::fprintf(stderr, "unknown argument %s\n", key.c_str());
      return 2;
    }
  }
  for (int signo : {SIGSEGV, SIGABRT, SIGBUS, SIGFPE, SIGILL}) std::signal(signo, save_input_and_die);
  std::vector<Bytes> corpus;
  std::error_code ec;
  if (!corpus_dir.empty() && std::filesystem::is_directory(corpus_dir, ec)) {
    for (const auto& entry : std::filesystem::directory_iterator(corpus_dir)) {
      if (!entry.is_regular_file()) continue;
      std::ifstream in(entry.path(), std::ios::binary);
      corpus.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
  }
  for (const Bytes& s : corpus) run(s);
  std::mt19937_64 rng(seed);
  for (long r = 0; r < runs; ++r) {
    if (!corpus.empty() && r % 4 != 3) {
      run(mutate(corpus[rng() % corpus.size()], corpus, rng, max_len));
    } else {
      Bytes random(rng() % (max_len + 1));
      for (auto& b : random) b = static_cast<std::uint8_t>(rng());
      run(random);
    }
  }
  std::printf("fuzz-random: %zu seeds, %ld runs, no crash\n", corpus.size(), runs);
  return 0;
}
