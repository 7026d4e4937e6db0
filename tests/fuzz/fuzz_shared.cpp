// tests/fuzz/fuzz_shared.cpp - libFuzzer target: a shared session's messages (app/session/shared/shared_message.hpp)
// as the host and a joiner dispatch them: the kind, then that kind's decoder. Decoders refuse bad input with
// tridex::Error; any other exception, a crash or a sanitizer report is a finding.
#include <cstdint>
#include <span>
#include <string>

#include "app/session/shared/shared_message.hpp"
#include "core/error.hpp"

namespace app = tridex::app;

/// One fuzz input as one message.
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::span<const unsigned char> b(data, size);
    const std::string from = "fuzz";
    try {
        switch (app::shared_kind(b, from)) {
            case app::SharedKind::kJoin: (void)app::decode_join(b, from); break;
            case app::SharedKind::kWelcome: (void)app::decode_welcome(b, from); break;
            case app::SharedKind::kSamples: (void)app::decode_samples(b, from); break;
            case app::SharedKind::kRequest: (void)app::decode_request(b, from); break;
            case app::SharedKind::kRecords:
            case app::SharedKind::kRecordsPacked: (void)app::decode_records(b, from); break;
            case app::SharedKind::kRefused: (void)app::decode_refused(b, from); break;
            case app::SharedKind::kPresence: (void)app::decode_presence(b, from); break;
            case app::SharedKind::kEnd: (void)app::decode_end(b, from); break;
        }
    } catch (const tridex::Error&) {
        // refused, as the host and the joiner refuse it
    }
    return 0;
}
