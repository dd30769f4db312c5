// How a built-in pass binds its shaders (shader::ShaderInterface, which vk::DescriptorWriter and
// every pass's set-up consult): by the GLSL names, with each mistake refused on the CPU and named:
// a name the shaders do not declare, a resource of the wrong kind, a declared binding left
// unwritten, and a C++ struct that does not mirror the push-constant block.
#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/paths.h"
#include "shader/shader_interface.h"

using namespace caustica;
using namespace caustica::shader;

namespace {

// What core/box_blur.comp pushes, as passes/box_blur.cpp mirrors it.
struct BlurParams {
  int32_t size[2];
  int32_t axis[2];
  int32_t radius;
};

}  // namespace

class ShaderBinding : public ::testing::Test {
 protected:
  ShaderCompiler compiler{data_dir() / "shaders"};
  ReflectedShader blur = compiler.compile_reflected("core/box_blur.comp");
  ShaderInterface interface {
    "blur_x", {
      { "core/box_blur.comp", &blur.reflection }
    }
  };

  size_t index_of(const std::string& name) const {
    const auto& bindings = interface.bindings();
    for (size_t i = 0; i < bindings.size(); ++i) {
      if (bindings[i].name == name) return i;
    }
    ADD_FAILURE() << name << " is not among the interface's bindings";
    return 0;
  }
};

namespace {

// The message of what `f` throws, or "" when it does not throw.
template <class F>
std::string refusal(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_F(ShaderBinding, TheLayoutComesFromTheShadersDeclarations) {
  ASSERT_EQ(interface.bindings().size(), 2u);
  EXPECT_EQ(interface.find("source", {BindingKind::sampled_image}).binding, 0u);
  EXPECT_EQ(interface.find("target", {BindingKind::storage_image}).binding, 1u);
  EXPECT_EQ(interface.push_size(), sizeof(BlurParams));
  EXPECT_TRUE(interface.declares("target"));
  EXPECT_FALSE(interface.declares("targets"));
}

TEST_F(ShaderBinding, ANameTheShaderDoesNotDeclareIsRefusedWithIt) {
  const std::string message = refusal([&] { interface.find("sourse", {BindingKind::sampled_image}); });
  EXPECT_NE(message.find("'sourse'"), std::string::npos) << message;
  EXPECT_NE(message.find("pass 'blur_x'"), std::string::npos) << message;
  EXPECT_NE(message.find("core/box_blur.comp"), std::string::npos) << message;
}

TEST_F(ShaderBinding, AResourceOfTheWrongKindIsRefused) {
  const std::string message = refusal([&] { interface.find("target", {BindingKind::sampled_image}); });
  EXPECT_NE(message.find("'target' is a storage image"), std::string::npos) << message;
}

TEST_F(ShaderBinding, ADeclaredBindingLeftUnwrittenIsRefusedWithItsName) {
  EXPECT_EQ(refusal([&] { interface.check_written({{index_of("source"), 0}, {index_of("target"), 0}}); }), "");
  const std::string message = refusal([&] { interface.check_written({{index_of("source"), 0}}); });
  EXPECT_NE(message.find("'target'"), std::string::npos) << message;
  EXPECT_NE(message.find("leaves unbound"), std::string::npos) << message;
  EXPECT_NE(message.find("core/box_blur.comp"), std::string::npos) << message;
}

// An array of samplers (lighting's shadow maps, one per light) is as long as the shader declares
// it, and each of its elements must be written.
TEST_F(ShaderBinding, EveryElementOfAnArrayMustBeWritten) {
  const ReflectedShader lighting = compiler.compile_reflected("scene/lighting.frag", {{"SHADOWS", "8"}});
  const ShaderInterface lit("lighting", {{"scene/lighting.frag", &lighting.reflection}});
  const InterfaceBinding& maps = lit.find("shadow_maps", {BindingKind::sampled_image});
  EXPECT_EQ(maps.count, 8u);  // SHADOWS
  const size_t index = static_cast<size_t>(&maps - lit.bindings().data());
  std::vector<std::pair<size_t, uint32_t>> written;
  for (size_t i = 0; i < lit.bindings().size(); ++i) {
    if (i != index) written.emplace_back(i, 0);
  }
  for (uint32_t element = 0; element < 8; ++element) {
    if (element != 3) written.emplace_back(index, element);
  }
  const std::string message = refusal([&] { lit.check_written(written); });
  EXPECT_NE(message.find("element 3 of 'shadow_maps'"), std::string::npos) << message;
  written.emplace_back(index, 3);
  EXPECT_EQ(refusal([&] { lit.check_written(written); }), "");
}

TEST_F(ShaderBinding, AFaithfulMirrorOfThePushConstantsIsAccepted) {
  EXPECT_EQ(refusal([&] {
              interface.check_push(
                  "BlurParams", sizeof(BlurParams),
                  {CAUSTICA_MIRRORED(BlurParams, size), CAUSTICA_MIRRORED(BlurParams, axis), CAUSTICA_MIRRORED(BlurParams, radius)});
            }),
            "");
}

TEST_F(ShaderBinding, AMirrorWithAMemberAtAnotherOffsetIsRefusedWithTheMember) {
  struct Swapped {
    int32_t size[2];
    int32_t radius;
    int32_t axis[2];
  };
  const std::string message = refusal([&] {
    interface.check_push("Swapped", sizeof(Swapped),
                         {CAUSTICA_MIRRORED(Swapped, size), CAUSTICA_MIRRORED(Swapped, axis), CAUSTICA_MIRRORED(Swapped, radius)});
  });
  EXPECT_NE(message.find("member 'axis' is at offset 8, Swapped has it at 12"), std::string::npos) << message;
}

TEST_F(ShaderBinding, AMirrorOfAnotherSizeIsRefused) {
  struct Longer {
    int32_t size[2];
    int32_t axis[2];
    int32_t radius;
    float extra;
  };
  const std::string size_only = refusal([&] {
    interface.check_push("Longer", sizeof(Longer),
                         {CAUSTICA_MIRRORED(Longer, size), CAUSTICA_MIRRORED(Longer, axis), CAUSTICA_MIRRORED(Longer, radius)});
  });
  EXPECT_NE(size_only.find("is 20 bytes, Longer is 24"), std::string::npos) << size_only;
  const std::string extra = refusal([&] {
    interface.check_push("Longer", sizeof(Longer),
                         {CAUSTICA_MIRRORED(Longer, size), CAUSTICA_MIRRORED(Longer, axis), CAUSTICA_MIRRORED(Longer, radius),
                          CAUSTICA_MIRRORED(Longer, extra)});
  });
  EXPECT_NE(extra.find("has no member 'extra'"), std::string::npos) << extra;
  const std::string missing = refusal([&] {
    interface.check_push("BlurParams", sizeof(BlurParams), {CAUSTICA_MIRRORED(BlurParams, size), CAUSTICA_MIRRORED(BlurParams, axis)});
  });
  EXPECT_NE(missing.find("member 'radius' has no counterpart in BlurParams"), std::string::npos) << missing;
}

TEST_F(ShaderBinding, StagesThatDeclareOneBindingDifferentlyAreRefused) {
  const ReflectedShader tonemap = compiler.compile_reflected("core/tonemap.comp");
  const ReflectedShader copy = compiler.compile_reflected("common/copy.comp");
  // Both declare source at 0 and target at 1; tonemap's Counters at 2 as well.
  EXPECT_EQ(refusal([&] {
              ShaderInterface("both", {{"core/tonemap.comp", &tonemap.reflection}, {"common/copy.comp", &copy.reflection}});
            }),
            "");
  const ReflectedShader temporal = compiler.compile_reflected("core/temporal_mean.comp");  // current at 0
  const std::string message = refusal([&] {
    ShaderInterface("clash", {{"core/box_blur.comp", &blur.reflection}, {"core/temporal_mean.comp", &temporal.reflection}});
  });
  EXPECT_NE(message.find("declares 'current' at set 0 binding 0, where core/box_blur.comp declares 'source'"), std::string::npos)
      << message;
}
