// tests/fuzz/fuzz_journal.cpp - libFuzzer target: parse_journal on the bytes of a session journal (.tdj), which
// must refuse a bad header and resynchronise past damaged records.
#include <cstdint>
#include <span>

#include "compute/journal/journal_reader.hpp"
#include "tests/fuzz/fuzz_support.hpp"

/// One fuzz input as the bytes of a journal.
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string path = "fuzz.tdj";
    tridex::fuzz::expect_clean(path, [&] { tridex::compute::parse_journal(std::span(data, size), path); });
    return 0;
}
