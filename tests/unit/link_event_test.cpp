#include "wheeltec/frames/link_event.hpp"

#include <gtest/gtest.h>
#include <linux/can/netlink.h>
#include <linux/if_link.h>
#include <linux/netlink.h>
#include <linux/rtnetlink.h>
#include <net/if.h>

#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace wheeltec {
namespace {

using Bytes = std::vector<std::uint8_t>;

void append_raw(Bytes& out, const void* data, std::size_t size) {
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  out.insert(out.end(), bytes, bytes + size);
}

void pad4(Bytes& out) {
  while (out.size() % 4 != 0) out.push_back(0);
}

Bytes attribute(std::uint16_t type, const void* data, std::size_t size) {
  Bytes out;
  const rtattr header{static_cast<unsigned short>(sizeof(rtattr) + size), type};
  append_raw(out, &header, sizeof(header));
  append_raw(out, data, size);
  pad4(out);
  return out;
}

Bytes name_attribute(const std::string& name) { return attribute(IFLA_IFNAME, name.c_str(), name.size() + 1); }

// One netlink message: header, then `body`, with nlmsg_len covering both; unpadded, as
// the last message of a datagram may be.
Bytes unpadded_message(std::uint16_t type, const Bytes& body, std::uint16_t flags = 0) {
  Bytes out;
  nlmsghdr header{};
  header.nlmsg_len = static_cast<std::uint32_t>(sizeof(nlmsghdr) + body.size());
  header.nlmsg_type = type;
  header.nlmsg_flags = flags;
  append_raw(out, &header, sizeof(header));
  out.insert(out.end(), body.begin(), body.end());
  return out;
}

// The same, padded to netlink's 4-byte alignment.
Bytes message(std::uint16_t type, const Bytes& body, std::uint16_t flags = 0) {
  Bytes out = unpadded_message(type, body, flags);
  pad4(out);
  return out;
}

Bytes link_message(std::uint16_t type, int index, unsigned flags, const std::vector<Bytes>& attributes,
                   std::uint16_t message_flags = 0) {
  Bytes body;
  ifinfomsg info{};
  info.ifi_family = AF_UNSPEC;
  info.ifi_index = index;
  info.ifi_flags = flags;
  append_raw(body, &info, sizeof(info));
  for (const auto& a : attributes) body.insert(body.end(), a.begin(), a.end());
  return message(type, body, message_flags);
}

Bytes error_message(int error) {
  Bytes body;
  nlmsgerr payload{};
  payload.error = error;
  append_raw(body, &payload, sizeof(payload));
  return message(NLMSG_ERROR, body);
}

Bytes concat(std::initializer_list<Bytes> parts) {
  Bytes out;
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

struct Parsed {
  LinkMessagesSummary summary;
  std::vector<LinkEvent> events;
  std::vector<std::string> names;  // copies: the events' views point into the buffer
  std::vector<std::string> kinds;
};

// Parses from a heap copy of exactly `bytes.size()` bytes, so that AddressSanitizer or
// valgrind would catch any read past the end.
Parsed parse(const Bytes& bytes) {
  Parsed out;
  auto exact = std::make_unique<std::uint8_t[]>(bytes.size() + (bytes.empty() ? 1 : 0));
  if (!bytes.empty()) std::memcpy(exact.get(), bytes.data(), bytes.size());
  out.summary = parse_link_messages(std::span<const std::uint8_t>(exact.get(), bytes.size()),
                                    [&](const LinkEvent& event) {
                                      out.events.push_back(event);
                                      out.names.emplace_back(event.name);
                                      out.kinds.emplace_back(event.kind);
                                    });
  return out;
}

TEST(LinkEvent, NewLinkUpWithItsName) {
  const auto parsed = parse(link_message(RTM_NEWLINK, 7, IFF_UP | IFF_RUNNING | IFF_NOARP,
                                         {attribute(IFLA_MTU, "\x10\0\0\0", 4), name_attribute("vcan0")}));
  ASSERT_EQ(parsed.events.size(), 1u);
  EXPECT_EQ(parsed.events[0].change, LinkChange::updated);
  EXPECT_EQ(parsed.events[0].index, 7);
  EXPECT_TRUE(parsed.events[0].up());
  EXPECT_EQ(parsed.names[0], "vcan0");
  EXPECT_FALSE(parsed.summary.malformed);
  EXPECT_FALSE(parsed.summary.done);
  EXPECT_FALSE(parsed.summary.error.has_value());
}

TEST(LinkEvent, NewLinkDownAndDelLink) {
  const auto parsed = parse(concat({link_message(RTM_NEWLINK, 3, IFF_NOARP, {name_attribute("can1")}),
                                    link_message(RTM_DELLINK, 3, 0, {name_attribute("can1")})}));
  ASSERT_EQ(parsed.events.size(), 2u);
  EXPECT_FALSE(parsed.events[0].up());
  EXPECT_EQ(parsed.events[0].change, LinkChange::updated);
  EXPECT_EQ(parsed.events[1].change, LinkChange::removed);
  EXPECT_EQ(parsed.names[1], "can1");
  EXPECT_EQ(parsed.summary.events, 2u);
}

Bytes nested(std::uint16_t type, const std::vector<Bytes>& attributes) {
  Bytes payload;
  for (const auto& a : attributes) payload.insert(payload.end(), a.begin(), a.end());
  return attribute(type, payload.data(), payload.size());
}

Bytes kind_attribute(const std::string& kind) { return attribute(IFLA_INFO_KIND, kind.c_str(), kind.size() + 1); }

Bytes bit_timing_attribute(std::uint32_t bitrate) {
  can_bittiming timing{};
  timing.bitrate = bitrate;
  timing.sample_point = 875;
  return attribute(IFLA_CAN_BITTIMING, &timing, sizeof(timing));
}

Bytes can_state_attribute(std::uint32_t state) { return attribute(IFLA_CAN_STATE, &state, sizeof(state)); }

TEST(LinkEvent, CanControllerGivesKindBitrateAndState) {
  const auto parsed = parse(link_message(
      RTM_NEWLINK, 4, IFF_UP,
      {name_attribute("can0"),
       nested(IFLA_LINKINFO, {kind_attribute("can"), nested(IFLA_INFO_DATA, {bit_timing_attribute(1000000),
                                                                             can_state_attribute(CAN_STATE_BUS_OFF)})})}));
  ASSERT_EQ(parsed.events.size(), 1u);
  EXPECT_EQ(parsed.names[0], "can0");
  EXPECT_EQ(parsed.kinds[0], "can");
  EXPECT_EQ(parsed.events[0].bitrate, std::optional<std::uint32_t>(1000000));
  EXPECT_EQ(parsed.events[0].can_state, std::optional<std::uint32_t>(CAN_STATE_BUS_OFF));
  EXPECT_FALSE(parsed.summary.malformed);
}

TEST(LinkEvent, VirtualInterfaceHasAKindButNoBitrate) {
  const auto parsed =
      parse(link_message(RTM_NEWLINK, 4, IFF_UP, {nested(IFLA_LINKINFO, {kind_attribute("vcan")}), name_attribute("vcan0")}));
  ASSERT_EQ(parsed.events.size(), 1u);
  EXPECT_EQ(parsed.kinds[0], "vcan");
  EXPECT_EQ(parsed.names[0], "vcan0");
  EXPECT_FALSE(parsed.events[0].bitrate.has_value());
  EXPECT_FALSE(parsed.events[0].can_state.has_value());
}

TEST(LinkEvent, UnsetBitrateIsAbsent) {
  const auto parsed = parse(link_message(
      RTM_NEWLINK, 4, 0, {nested(IFLA_LINKINFO, {kind_attribute("can"), nested(IFLA_INFO_DATA, {bit_timing_attribute(0)})})}));
  ASSERT_EQ(parsed.events.size(), 1u);
  EXPECT_FALSE(parsed.events[0].bitrate.has_value());
}

TEST(LinkEvent, OtherKindsDataIsNotReadAsCan) {
  // vxcan's IFLA_INFO_DATA holds a peer description whose attribute numbers overlap CAN's.
  const auto parsed = parse(link_message(
      RTM_NEWLINK, 4, 0,
      {nested(IFLA_LINKINFO, {kind_attribute("vxcan"), nested(IFLA_INFO_DATA, {bit_timing_attribute(500000)})})}));
  ASSERT_EQ(parsed.events.size(), 1u);
  EXPECT_EQ(parsed.kinds[0], "vxcan");
  EXPECT_FALSE(parsed.events[0].bitrate.has_value());
}

TEST(LinkEvent, NestedAttributeRunningPastItsParentIsMalformed) {
  Bytes data = nested(IFLA_INFO_DATA, {bit_timing_attribute(1000000)});
  // The inner attribute claims 8 bytes more than IFLA_INFO_DATA holds.
  rtattr inner;
  std::memcpy(&inner, data.data() + sizeof(rtattr), sizeof(inner));
  inner.rta_len = static_cast<unsigned short>(inner.rta_len + 8);
  std::memcpy(data.data() + sizeof(rtattr), &inner, sizeof(inner));
  const auto parsed =
      parse(link_message(RTM_NEWLINK, 4, IFF_UP, {nested(IFLA_LINKINFO, {kind_attribute("can"), data}), name_attribute("can0")}));
  EXPECT_TRUE(parsed.summary.malformed);
  EXPECT_TRUE(parsed.events.empty());
}

TEST(LinkEvent, MessageWithoutNameHasEmptyName) {
  const auto parsed = parse(link_message(RTM_NEWLINK, 2, IFF_UP, {}));
  ASSERT_EQ(parsed.events.size(), 1u);
  EXPECT_TRUE(parsed.names[0].empty());
  EXPECT_EQ(parsed.events[0].index, 2);
}

TEST(LinkEvent, NameWithoutTerminatorStopsAtTheAttributeEnd) {
  const auto parsed = parse(link_message(RTM_NEWLINK, 2, IFF_UP, {attribute(IFLA_IFNAME, "vcan0", 5),
                                                                   attribute(IFLA_MTU, "\x10\0\0\0", 4)}));
  ASSERT_EQ(parsed.events.size(), 1u);
  EXPECT_EQ(parsed.names[0], "vcan0");
}

TEST(LinkEvent, OtherMessageTypesAreSkippedNotMistakenForLinks) {
  Bytes address_body(sizeof(ifaddrmsg), 0);
  const auto parsed = parse(concat({message(RTM_NEWADDR, address_body), message(NLMSG_NOOP, {}),
                                    link_message(RTM_NEWLINK, 4, IFF_UP, {name_attribute("vcan0")})}));
  ASSERT_EQ(parsed.events.size(), 1u);
  EXPECT_EQ(parsed.summary.other_messages, 2u);
  EXPECT_EQ(parsed.names[0], "vcan0");
}

TEST(LinkEvent, MultipartAnswerEndsAtDone) {
  const auto parsed = parse(concat({link_message(RTM_NEWLINK, 1, IFF_UP, {name_attribute("lo")}, NLM_F_MULTI),
                                    link_message(RTM_NEWLINK, 5, IFF_UP, {name_attribute("vcan0")}, NLM_F_MULTI),
                                    message(NLMSG_DONE, Bytes(sizeof(int), 0), NLM_F_MULTI),
                                    link_message(RTM_NEWLINK, 9, IFF_UP, {name_attribute("after")})}));
  EXPECT_TRUE(parsed.summary.done);
  ASSERT_EQ(parsed.events.size(), 2u);
  EXPECT_EQ(parsed.names[0], "lo");
  EXPECT_EQ(parsed.names[1], "vcan0");
}

TEST(LinkEvent, ErrorMessageReportsThePositiveErrnoAndStops) {
  const auto parsed = parse(concat({error_message(-ENODEV), link_message(RTM_NEWLINK, 5, IFF_UP, {})}));
  ASSERT_TRUE(parsed.summary.error.has_value());
  EXPECT_EQ(*parsed.summary.error, ENODEV);
  EXPECT_TRUE(parsed.events.empty());
}

TEST(LinkEvent, AcknowledgementIsNotAnError) {
  const auto parsed = parse(concat({error_message(0), link_message(RTM_NEWLINK, 5, IFF_UP, {})}));
  EXPECT_FALSE(parsed.summary.error.has_value());
  EXPECT_EQ(parsed.events.size(), 1u);
}

TEST(LinkEvent, ErrorMessageTooShortForItsCodeIsMalformed) {
  const auto parsed = parse(message(NLMSG_ERROR, Bytes{1, 2}));
  EXPECT_TRUE(parsed.summary.malformed);
  EXPECT_FALSE(parsed.summary.error.has_value());
}

// Found by fuzz_link_messages: negating INT_MIN was undefined behaviour.
TEST(LinkEvent, ErrorCodeOutsideTheErrnoRangeIsMalformed) {
  for (const int code : {std::numeric_limits<int>::min(), -4096, 4096, std::numeric_limits<int>::max()}) {
    const auto parsed = parse(error_message(code));
    EXPECT_TRUE(parsed.summary.malformed) << code;
    EXPECT_FALSE(parsed.summary.error.has_value()) << code;
  }
  EXPECT_EQ(parse(error_message(-4095)).summary.error, 4095);
}

TEST(LinkEvent, EmptyBufferIsNothing) {
  const auto parsed = parse({});
  EXPECT_EQ(parsed.summary.events, 0u);
  EXPECT_FALSE(parsed.summary.malformed);
}

TEST(LinkEvent, EveryTruncationOfAValidDatagramIsReportedAndNeverOverread) {
  const Bytes whole = concat({link_message(RTM_NEWLINK, 5, IFF_UP, {name_attribute("vcan0")}),
                              link_message(RTM_DELLINK, 5, 0, {name_attribute("vcan0")})});
  const std::size_t first_length = link_message(RTM_NEWLINK, 5, IFF_UP, {name_attribute("vcan0")}).size();
  for (std::size_t size = 0; size < whole.size(); ++size) {
    const auto parsed = parse(Bytes(whole.begin(), whole.begin() + static_cast<std::ptrdiff_t>(size)));
    SCOPED_TRACE("truncated to " + std::to_string(size) + " bytes");
    if (size == 0 || size == first_length) {
      EXPECT_FALSE(parsed.summary.malformed);
    } else {
      EXPECT_TRUE(parsed.summary.malformed);
    }
    EXPECT_EQ(parsed.events.size(), size >= first_length ? 1u : 0u);
  }
}

TEST(LinkEvent, LengthShorterThanTheHeaderIsMalformed) {
  Bytes bytes = link_message(RTM_NEWLINK, 5, IFF_UP, {name_attribute("vcan0")});
  nlmsghdr header;
  std::memcpy(&header, bytes.data(), sizeof(header));
  header.nlmsg_len = 8;
  std::memcpy(bytes.data(), &header, sizeof(header));
  const auto parsed = parse(bytes);
  EXPECT_TRUE(parsed.summary.malformed);
  EXPECT_TRUE(parsed.events.empty());
}

TEST(LinkEvent, LengthPastTheBufferIsMalformed) {
  Bytes bytes = link_message(RTM_NEWLINK, 5, IFF_UP, {name_attribute("vcan0")});
  nlmsghdr header;
  std::memcpy(&header, bytes.data(), sizeof(header));
  header.nlmsg_len = 0xFFFFFFF0u;
  std::memcpy(bytes.data(), &header, sizeof(header));
  const auto parsed = parse(bytes);
  EXPECT_TRUE(parsed.summary.malformed);
  EXPECT_TRUE(parsed.events.empty());
}

TEST(LinkEvent, LinkMessageTooShortForItsBodyIsMalformed) {
  const auto parsed = parse(message(RTM_NEWLINK, Bytes(8, 0)));
  EXPECT_TRUE(parsed.summary.malformed);
  EXPECT_TRUE(parsed.events.empty());
}

TEST(LinkEvent, AttributeRunningPastTheMessageIsMalformed) {
  Bytes name = name_attribute("vcan0");
  rtattr header;
  std::memcpy(&header, name.data(), sizeof(header));
  header.rta_len = 200;
  std::memcpy(name.data(), &header, sizeof(header));
  // A second message follows, so the attribute's claimed length would reach into it.
  const auto parsed = parse(concat({link_message(RTM_NEWLINK, 5, IFF_UP, {name}),
                                    link_message(RTM_NEWLINK, 6, IFF_UP, {name_attribute("vcan1")})}));
  EXPECT_TRUE(parsed.summary.malformed);
  EXPECT_TRUE(parsed.events.empty()) << "a message whose attributes are inconsistent must not be half-delivered";
}

TEST(LinkEvent, AttributeShorterThanItsHeaderIsMalformed) {
  Bytes bad(sizeof(rtattr), 0);
  const rtattr header{2, IFLA_IFNAME};
  std::memcpy(bad.data(), &header, sizeof(header));
  const auto parsed = parse(link_message(RTM_NEWLINK, 5, IFF_UP, {bad}));
  EXPECT_TRUE(parsed.summary.malformed);
  EXPECT_TRUE(parsed.events.empty());
}

TEST(LinkEvent, TrailingBytesShorterThanAnAttributeHeaderAreMalformed) {
  Bytes body;
  ifinfomsg info{};
  info.ifi_index = 5;
  append_raw(body, &info, sizeof(info));
  const Bytes name = name_attribute("vcan0");
  body.insert(body.end(), name.begin(), name.end());
  body.push_back(0xAB);
  body.push_back(0xCD);
  const auto parsed = parse(unpadded_message(RTM_NEWLINK, body));
  EXPECT_TRUE(parsed.summary.malformed);
}

TEST(LinkEvent, UnpaddedFinalMessageIsAccepted) {
  // The last message's length need not be a multiple of 4: nothing follows it.
  Bytes body;
  ifinfomsg info{};
  info.ifi_index = 8;
  info.ifi_flags = IFF_UP;
  append_raw(body, &info, sizeof(info));
  const rtattr name_header{static_cast<unsigned short>(sizeof(rtattr) + 3), IFLA_IFNAME};
  append_raw(body, &name_header, sizeof(name_header));
  append_raw(body, "ab", 3);
  const auto parsed = parse(unpadded_message(RTM_NEWLINK, body));
  EXPECT_FALSE(parsed.summary.malformed);
  ASSERT_EQ(parsed.events.size(), 1u);
  EXPECT_EQ(parsed.names[0], "ab");
}

TEST(LinkEvent, GarbageNeverCrashesAndNeverYieldsEventsPastTheBuffer) {
  // Deterministic pseudo-random buffers, some starting with a plausible link header.
  std::uint32_t state = 12345;
  const auto next = [&] {
    state = state * 1664525u + 1013904223u;
    return static_cast<std::uint8_t>(state >> 24);
  };
  const Bytes valid = link_message(RTM_NEWLINK, 5, IFF_UP, {name_attribute("vcan0")});
  for (int round = 0; round < 2000; ++round) {
    Bytes bytes = (round % 2 == 0) ? valid : Bytes{};
    const std::size_t extra = next() % 64;
    for (std::size_t i = 0; i < extra; ++i) bytes.push_back(next());
    for (std::size_t i = 0; i < bytes.size() && round % 2 == 0; i += 7) bytes[i] ^= next() & 0x0F;
    const auto parsed = parse(bytes);
    for (const auto& name : parsed.names) EXPECT_LE(name.size(), bytes.size());
  }
}

}  // namespace
}  // namespace wheeltec
