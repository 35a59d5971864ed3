// A stand-in for libFuzzer's main() where libFuzzer is not available (GCC
// builds, the default test suite): it runs the fuzz target on every file of
// the corpus directories or files named on the command line, then on
// `--random N` pseudo-random byte strings (a fixed seed, so a run is
// repeatable; lengths up to 1024 bytes, half of them mutations of corpus
// entries), stopping early after `--seconds S`. A finding aborts inside the
// target (HEDRA_FUZZ_CHECK) or crashes, which fails the ctest; the input
// that did it is first written to `fuzz-finding.bin` in the working
// directory (a signal handler, async-signal-safe calls only), so it can be
// replayed (`fuzz_<target> fuzz-finding.bin`) and added to the corpus.
#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

const std::vector<std::uint8_t>* current_input = nullptr;

extern "C" void save_finding(int signal_number) {
  if (current_input != nullptr) {
    const int fd = ::open("fuzz-finding.bin", O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      const ssize_t written = ::write(fd, current_input->data(), current_input->size());
      (void)written;
      ::close(fd);
    }
    static const char note[] = "fuzz_driver: the input is saved in fuzz-finding.bin\n";
    const ssize_t noted = ::write(2, note, sizeof note - 1);
    (void)noted;
  }
  std::signal(signal_number, SIG_DFL);
  std::raise(signal_number);
}

}  // namespace

int main(int argc, char** argv) {
  for (int signal_number : {SIGABRT, SIGSEGV, SIGFPE, SIGBUS, SIGILL}) std::signal(signal_number, save_finding);
  long random_runs = 0;
  double seconds = 1e9;
  std::vector<std::vector<std::uint8_t>> corpus;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--random" && i + 1 < argc) {
      random_runs = std::atol(argv[++i]);
    } else if (arg == "--seconds" && i + 1 < argc) {
      seconds = std::atof(argv[++i]);
    } else {
      std::vector<std::filesystem::path> files;
      if (std::filesystem::is_directory(arg)) {
        for (const auto& entry : std::filesystem::directory_iterator(arg))
          if (entry.is_regular_file()) files.push_back(entry.path());
      } else {
        files.push_back(arg);
      }
      for (const auto& file : files) {
        std::ifstream in(file, std::ios::binary);
        if (!in) {
          std::fprintf(stderr, "fuzz_driver: cannot read %s\n", file.c_str());
          return 2;
        }
        corpus.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
      }
    }
  }
  const auto start = std::chrono::steady_clock::now();
  for (const auto& input : corpus) {
    current_input = &input;
    LLVMFuzzerTestOneInput(input.data(), input.size());
  }

  std::mt19937_64 rng(20261122);
  long done = 0;
  std::vector<std::uint8_t> buffer;
  for (; done < random_runs; ++done) {
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > seconds) break;
    if (!corpus.empty() && rng() % 2 == 0) {
      buffer = corpus[rng() % corpus.size()];
      const int flips = 1 + static_cast<int>(rng() % 8);
      for (int k = 0; k < flips && !buffer.empty(); ++k)
        buffer[rng() % buffer.size()] = static_cast<std::uint8_t>(rng());
      if (rng() % 4 == 0) buffer.resize(rng() % (buffer.size() + 64), static_cast<std::uint8_t>(rng()));
    } else {
      buffer.resize(rng() % 1025);
      for (std::uint8_t& byte : buffer) byte = static_cast<std::uint8_t>(rng());
    }
    current_input = &buffer;
    LLVMFuzzerTestOneInput(buffer.data(), buffer.size());
  }
  current_input = nullptr;
  std::printf("%zu corpus inputs and %ld random inputs run, 0 findings\n", corpus.size(), done);
  return 0;
}
