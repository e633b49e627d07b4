#include "rove/serialization/object_io.h"

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <thread>

#include "rove/core/error.h"
#include "rove/serialization/stl.h"
#include "test_util.h"

namespace demo {

class Circle final : public rove::Serializable {
 public:
  double radius = 0;
  std::string_view class_name() const override { return "demo.Circle"; }
  std::uint8_t version() const override { return 0; }
  void save_payload(rove::OutArchive& ar) const override { ar << radius; }
  void load_payload(rove::InArchive& ar, std::uint8_t) override { ar >> radius; }
};

// Version 0 had only the text; version 1 added the font size.
class Label final : public rove::Serializable {
 public:
  std::string text;
  std::uint16_t size = 12;
  std::string_view class_name() const override { return "demo.Label"; }
  std::uint8_t version() const override { return 1; }
  void save_payload(rove::OutArchive& ar) const override { ar << text << size; }
  void load_payload(rove::InArchive& ar, std::uint8_t version) override {
    ar >> text;
    if (version >= 1) {
      ar >> size;
    } else {
      size = 12;
    }
  }
};

// Holds other objects: exercises nesting.
class Group final : public rove::Serializable {
 public:
  std::vector<std::unique_ptr<rove::Serializable>> items;
  const rove::ClassRegistry* registry = &rove::ClassRegistry::global();
  std::string_view class_name() const override { return "demo.Group"; }
  std::uint8_t version() const override { return 0; }
  void save_payload(rove::OutArchive& ar) const override {
    ar.write_length(items.size(), "items");
    for (const auto& i : items) rove::write_object(ar, *i);
  }
  void load_payload(rove::InArchive& ar, std::uint8_t) override {
    const std::uint32_t n = ar.read_length("items", 6);
    items.clear();
    for (std::uint32_t i = 0; i < n; ++i) items.push_back(rove::read_object(ar, *registry));
  }
};

class Unregistered final : public rove::Serializable {
 public:
  std::string_view class_name() const override { return "demo.Unregistered"; }
  std::uint8_t version() const override { return 0; }
  void save_payload(rove::OutArchive& ar) const override { ar << std::uint8_t{1}; }
  void load_payload(rove::InArchive& ar, std::uint8_t) override {
    (void)ar.read_scalar<std::uint8_t>();
  }
};

// Registered in the global registry by a static registrar.
const rove::Registrar<Group> kRegisterGroup;
const rove::Registrar<Circle> kRegisterCircle;
const rove::Registrar<Label> kRegisterLabel;

}  // namespace demo

namespace rove {
namespace {

using test::from_hex;
using test::to_hex;

std::vector<std::byte> write_all(std::initializer_list<const Serializable*> objs) {
  MemoryOutStream out;
  OutArchive ar(out);
  for (const auto* o : objs) write_object(ar, *o);
  return out.take();
}

TEST(ObjectIo, MixedStreamReadsBackWithoutKnowingTypes) {
  demo::Circle c;
  c.radius = 2.5;
  demo::Label l;
  l.text = "dock";
  l.size = 20;
  const auto bytes = write_all({&c, &l, &c});

  MemoryInStream in{std::span<const std::byte>(bytes)};
  InArchive ar(in);
  std::vector<std::string> names;
  while (!ar.at_end()) {
    auto obj = read_object(ar);
    names.emplace_back(obj->class_name());
    if (auto* circle = dynamic_cast<demo::Circle*>(obj.get())) {
      EXPECT_EQ(circle->radius, 2.5);
    }
    if (auto* label = dynamic_cast<demo::Label*>(obj.get())) {
      EXPECT_EQ(label->text, "dock");
      EXPECT_EQ(label->size, 20);
    }
  }
  EXPECT_EQ(names, (std::vector<std::string>{"demo.Circle", "demo.Label", "demo.Circle"}));
}

TEST(ObjectIo, FrozenRecordLayout) {
  demo::Label l;
  l.text = "a";
  l.size = 0x0102;
  EXPECT_EQ(to_hex(write_all({&l})),
            "0a 00 00 00 64 65 6d 6f 2e 4c 61 62 65 6c 01 01 00 00 00 61 02 01 88");
}

// A demo.Label written by version 0 (frozen bytes) still loads.
TEST(ObjectIo, OldVersionRecordStillLoads) {
  const auto v0 = from_hex("0a 00 00 00 64 65 6d 6f 2e 4c 61 62 65 6c 00 02 00 00 00 68 69 88");
  MemoryInStream in{std::span<const std::byte>(v0)};
  InArchive ar(in);
  const auto label = read_object_as<demo::Label>(ar);
  EXPECT_EQ(label->text, "hi");
  EXPECT_EQ(label->size, 12);
  EXPECT_TRUE(ar.at_end());
}

TEST(ObjectIo, NewerVersionIsRejectedNamingClassVersionAndOffset) {
  const auto v9 = from_hex("0a 00 00 00 64 65 6d 6f 2e 4c 61 62 65 6c 09 00 00 00 00 00 00 88");
  MemoryInStream in(std::span<const std::byte>(v9), "labels.bin");
  InArchive ar(in);
  try {
    (void)read_object(ar);
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().offset, 14u);
    EXPECT_EQ(e.location().field, "demo.Label");
    EXPECT_NE(e.problem().find("version 9"), std::string::npos) << e.what();
  }
}

TEST(ObjectIo, UnknownClassNameIsRejectedNamingClassAndOffset) {
  demo::Circle c;
  demo::Unregistered u;
  const auto bytes = write_all({&c, &u});
  MemoryInStream in(std::span<const std::byte>(bytes), "mixed.bin");
  InArchive ar(in);
  (void)read_object(ar);
  const std::uint64_t second = ar.offset();
  EXPECT_EQ(second, 4u + 11u + 1u + 8u + 1u);
  try {
    (void)read_object(ar);
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().offset, second);
    EXPECT_EQ(e.location().field, "demo.Unregistered");
    EXPECT_NE(std::string(e.what()).find("mixed.bin"), std::string::npos);
  }
}

TEST(ObjectIo, WrongEndMarkerIsRejected) {
  // A Circle whose payload has one byte too many.
  demo::Circle c;
  auto bytes = write_all({&c});
  bytes.insert(bytes.end() - 1, std::byte{0});
  MemoryInStream in{std::span<const std::byte>(bytes)};
  InArchive ar(in);
  try {
    (void)read_object(ar);
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.location().offset, 4u + 11u + 1u + 8u);
    EXPECT_EQ(e.location().field, "demo.Circle");
  }
}

TEST(ObjectIo, HugeOrEmptyClassNameLengthIsRejected) {
  for (const char* hex : {"ff ff ff ff 41", "00 00 00 00", "00 01 00 00 41"}) {
    const auto bytes = from_hex(hex);
    MemoryInStream in{std::span<const std::byte>(bytes)};
    InArchive ar(in);
    try {
      (void)read_object(ar);
      ADD_FAILURE() << hex;
    } catch (const ParseError& e) {
      EXPECT_EQ(e.location().offset, 0u);
    }
  }
}

TEST(ObjectIo, NestedObjectsRoundTripAndDepthIsBounded) {
  auto inner = std::make_unique<demo::Group>();
  inner->items.push_back(std::make_unique<demo::Circle>());
  demo::Group outer;
  outer.items.push_back(std::move(inner));
  outer.items.push_back(std::make_unique<demo::Label>());
  const auto bytes = write_all({&outer});
  {
    MemoryInStream in{std::span<const std::byte>(bytes)};
    InArchive ar(in);
    const auto back = read_object_as<demo::Group>(ar);
    ASSERT_EQ(back->items.size(), 2u);
    EXPECT_EQ(back->items[0]->class_name(), "demo.Group");
    EXPECT_EQ(back->items[1]->class_name(), "demo.Label");
  }
  {
    MemoryInStream in{std::span<const std::byte>(bytes)};
    InArchive ar(in, ArchiveLimits{.max_nesting = 1});
    EXPECT_THROW((void)read_object(ar), ParseError);
  }
}

TEST(ObjectIo, ReadObjectAsRejectsAnotherType) {
  demo::Circle c;
  const auto bytes = write_all({&c});
  MemoryInStream in{std::span<const std::byte>(bytes)};
  InArchive ar(in);
  EXPECT_THROW((void)read_object_as<demo::Label>(ar), ParseError);
}

TEST(ObjectIo, EveryTruncationIsAParseError) {
  demo::Label l;
  l.text = "truncate me";
  demo::Group g;
  g.items.push_back(std::make_unique<demo::Circle>());
  const auto bytes = write_all({&l, &g});
  for (std::size_t k = 0; k < bytes.size(); ++k) {
    MemoryInStream in(std::span<const std::byte>(bytes.data(), k));
    InArchive ar(in);
    try {
      while (true) (void)read_object(ar);
    } catch (const ParseError& e) {
      ASSERT_TRUE(e.location().offset.has_value());
      EXPECT_LE(*e.location().offset, k);
    }
  }
}

TEST(ClassRegistry, ExplicitRegistrationAndDuplicates) {
  ClassRegistry reg;
  EXPECT_FALSE(reg.contains("demo.Circle"));
  EXPECT_EQ(reg.create("demo.Circle"), nullptr);
  reg.add<demo::Circle>();
  EXPECT_TRUE(reg.contains("demo.Circle"));
  EXPECT_THROW(reg.add<demo::Circle>(), InvalidArgument);
  EXPECT_NO_THROW(reg.add<demo::Circle>(true));
  EXPECT_THROW(reg.add("", [] { return std::make_unique<demo::Circle>(); }), InvalidArgument);
  EXPECT_THROW(reg.add("x", ClassRegistry::Factory{}), InvalidArgument);
  reg.add<demo::Label>();
  EXPECT_EQ(reg.names(), (std::vector<std::string>{"demo.Circle", "demo.Label"}));

  // A stream with a class registered globally but not in this registry.
  demo::Group g;
  const auto bytes = write_all({&g});
  MemoryInStream in{std::span<const std::byte>(bytes)};
  InArchive ar(in);
  EXPECT_THROW((void)read_object(ar, reg), ParseError);
}

TEST(ClassRegistry, StaticRegistrarsFillTheGlobalRegistry) {
  EXPECT_TRUE(ClassRegistry::global().contains("demo.Circle"));
  EXPECT_TRUE(ClassRegistry::global().contains("demo.Label"));
  EXPECT_TRUE(ClassRegistry::global().contains("demo.Group"));
  EXPECT_FALSE(ClassRegistry::global().contains("demo.Unregistered"));
}

TEST(ClassRegistry, ConcurrentRegistrationAndLookupAgree) {
  ClassRegistry reg;
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&reg, t] {
      for (int i = 0; i < 200; ++i) {
        const std::string name = fmt::format("c{}_{}", t, i);
        reg.add(name, [] { return std::make_unique<demo::Circle>(); });
        EXPECT_NE(reg.create(name), nullptr);
      }
    });
  }
  for (auto& th : threads) th.join();
  EXPECT_EQ(reg.names().size(), 800u);
}

}  // namespace
}  // namespace rove
