#include "vk/context.h"

#include <cstdlib>
#include <cstring>

#ifdef MPUMESH_KEEP_DRIVERS_LOADED
#include <dlfcn.h>
#include <link.h>
#endif

#include "vk/vk_check.h"

namespace mpumesh::vk {
namespace {

const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

bool env_on(const char* name) {
  const char* v = std::getenv(name);
  return v && *v && std::strcmp(v, "0") != 0;
}

std::string type_name(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
    default: return "other";
  }
}

int type_rank(const std::string& t) {
  if (t == "discrete") return 0;
  if (t == "integrated") return 1;
  if (t == "virtual") return 2;
  if (t == "cpu") return 3;
  return 4;
}

// vkDestroyInstance, which unloads the drivers and layers the instance opened. Sanitized
// builds (MPUMESH_SANITIZE) first mark every shared library in the process RTLD_NODELETE,
// so that those stay mapped until exit: LeakSanitizer then still sees the drivers'
// globals (lavapipe keeps a realloc'd 128-byte table in one for the whole process) and
// can name the module of what is left, so scripts/sanitize.sh's suppressions apply;
// otherwise a driver's live memory is reported as a direct leak from an
// "<unknown module>".
void destroy_instance(VkInstance inst) {
#ifdef MPUMESH_KEEP_DRIVERS_LOADED
  std::vector<std::string> names;
  dl_iterate_phdr(
      [](dl_phdr_info* info, size_t, void* out) {
        if (info->dlpi_name && *info->dlpi_name) static_cast<std::vector<std::string>*>(out)->push_back(info->dlpi_name);
        return 0;
      },
      &names);
  for (const auto& n : names)
    if (void* h = dlopen(n.c_str(), RTLD_LAZY | RTLD_NOLOAD | RTLD_NODELETE)) dlclose(h);
#endif
  vkDestroyInstance(inst, nullptr);
}

bool layer_available(const char* name) {
  uint32_t n = 0;
  vkEnumerateInstanceLayerProperties(&n, nullptr);
  std::vector<VkLayerProperties> layers(n);
  vkEnumerateInstanceLayerProperties(&n, layers.data());
  for (const auto& l : layers)
    if (std::strcmp(l.layerName, name) == 0) return true;
  return false;
}

VkInstance make_instance(bool validation) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "mpumesh";
  app.apiVersion = VK_API_VERSION_1_1;
  VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ci.pApplicationInfo = &app;
  const char* ext = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
  if (validation) {
    ci.enabledLayerCount = 1;
    ci.ppEnabledLayerNames = &kValidationLayer;
    ci.enabledExtensionCount = 1;
    ci.ppEnabledExtensionNames = &ext;
  }
  VkInstance inst = VK_NULL_HANDLE;
  VkResult r = vkCreateInstance(&ci, nullptr, &inst);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER || r == VK_ERROR_INITIALIZATION_FAILED)
    throw NoVulkanDevice(std::string("no Vulkan driver found (vkCreateInstance: ") + result_name(r) +
                         "); install mesa-vulkan-drivers for the software device");
  VK_CHECK(r);
  return inst;
}

std::vector<VkPhysicalDevice> physical_devices(VkInstance inst) {
  uint32_t n = 0;
  VK_CHECK(vkEnumeratePhysicalDevices(inst, &n, nullptr));
  std::vector<VkPhysicalDevice> d(n);
  if (n) VK_CHECK(vkEnumeratePhysicalDevices(inst, &n, d.data()));
  return d;
}

int compute_family(VkPhysicalDevice pd) {
  uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
  std::vector<VkQueueFamilyProperties> q(n);
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, q.data());
  // A family that also draws, where there is one, so that the renderer shares the queue.
  const VkQueueFlags both = VK_QUEUE_COMPUTE_BIT | VK_QUEUE_GRAPHICS_BIT;
  for (uint32_t i = 0; i < n; ++i)
    if ((q[i].queueFlags & both) == both) return int(i);
  for (uint32_t i = 0; i < n; ++i)
    if (q[i].queueFlags & VK_QUEUE_COMPUTE_BIT) return int(i);
  return -1;
}

DeviceInfo describe(VkPhysicalDevice pd, int index) {
  VkPhysicalDeviceProperties p;
  vkGetPhysicalDeviceProperties(pd, &p);
  VkPhysicalDeviceMemoryProperties m;
  vkGetPhysicalDeviceMemoryProperties(pd, &m);
  DeviceInfo d;
  d.index = index;
  d.name = p.deviceName;
  d.type = type_name(p.deviceType);
  d.api_version = p.apiVersion;
  for (uint32_t h = 0; h < m.memoryHeapCount; ++h)
    if (m.memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) d.device_local_bytes += m.memoryHeaps[h].size;
  d.has_compute = compute_family(pd) >= 0;
  d.driver = std::to_string(VK_VERSION_MAJOR(p.driverVersion)) + "." + std::to_string(VK_VERSION_MINOR(p.driverVersion)) +
             "." + std::to_string(VK_VERSION_PATCH(p.driverVersion));
  return d;
}

}  // namespace

std::vector<DeviceInfo> list_devices() {
  std::vector<DeviceInfo> out;
  VkInstance inst = VK_NULL_HANDLE;
  try {
    inst = make_instance(false);
  } catch (const std::exception&) {
    return out;
  }
  try {
    auto pds = physical_devices(inst);
    for (size_t i = 0; i < pds.size(); ++i) out.push_back(describe(pds[i], int(i)));
  } catch (const std::exception&) {
  }
  destroy_instance(inst);
  return out;
}

int default_device_index(const std::vector<DeviceInfo>& devices, bool hardware_only) {
  int best = -1;
  for (const auto& d : devices) {
    if (!d.has_compute || (hardware_only && d.is_software())) continue;
    if (best < 0 || type_rank(d.type) < type_rank(devices[size_t(best)].type)) best = d.index;
  }
  return best;
}

Context::Context(const ContextOptions& opt) {
  validation_ = opt.validation || env_on("MPUMESH_VALIDATION");
  if (validation_ && !layer_available(kValidationLayer))
    throw NoVulkanDevice("Vulkan validation was asked for but VK_LAYER_KHRONOS_validation is not installed "
                         "(package vulkan-validationlayers)");
  instance_ = make_instance(validation_);
  try {
    if (validation_) {
      VkDebugUtilsMessengerCreateInfoEXT mi{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
      mi.messageSeverity =
          VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
      mi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
      mi.pfnUserCallback = &Context::on_message;
      mi.pUserData = this;
      auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
          vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
      if (!create) throw NoVulkanDevice("VK_EXT_debug_utils is not available for validation");
      VK_CHECK(create(instance_, &mi, nullptr, &messenger_));
    }
    auto pds = physical_devices(instance_);
    std::vector<DeviceInfo> infos;
    for (size_t i = 0; i < pds.size(); ++i) infos.push_back(describe(pds[i], int(i)));
    int index = opt.device_index;
    if (index >= 0) {
      if (index >= int(pds.size()))
        throw NoVulkanDevice("--device " + std::to_string(index) + ": only " + std::to_string(pds.size()) +
                             " Vulkan device(s) found (see `mpumesh devices`)");
      if (!infos[size_t(index)].has_compute)
        throw NoVulkanDevice("--device " + std::to_string(index) + ": the device has no compute queue");
    } else {
      index = default_device_index(infos, opt.hardware_only);
    }
    if (index < 0)
      throw NoVulkanDevice(pds.empty() ? "no Vulkan device found"
                                       : "no suitable Vulkan device found (" + std::to_string(pds.size()) +
                                             " device(s), none hardware with a compute queue)");
    physical_ = pds[size_t(index)];
    info_ = infos[size_t(index)];
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(physical_, &props);
    limits_ = props.limits;
    timestamp_period_ = props.limits.timestampPeriod;
    vkGetPhysicalDeviceMemoryProperties(physical_, &mem_props_);
    const uint32_t family = uint32_t(compute_family(physical_));
    uint32_t nq = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &nq, nullptr);
    std::vector<VkQueueFamilyProperties> qf(nq);
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &nq, qf.data());
    timestamps_ = qf[family].timestampValidBits > 0 && props.limits.timestampComputeAndGraphics;
    graphics_ = (qf[family].queueFlags & VK_QUEUE_GRAPHICS_BIT) != 0;
    const float priority = 1.0f;
    VkDeviceQueueCreateInfo qi{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qi.queueFamilyIndex = family;
    qi.queueCount = 1;
    qi.pQueuePriorities = &priority;
    VkDeviceCreateInfo di{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    di.queueCreateInfoCount = 1;
    di.pQueueCreateInfos = &qi;
    VkResult r = vkCreateDevice(physical_, &di, nullptr, &device_);
    if (r != VK_SUCCESS)
      throw NoVulkanDevice("cannot create a Vulkan device on '" + info_.name + "': " + result_name(r));
    vkGetDeviceQueue(device_, family, 0, &queue_);
    VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pi.queueFamilyIndex = family;
    VK_CHECK(vkCreateCommandPool(device_, &pi, nullptr, &pool_));
  } catch (...) {
    destroy();
    throw;
  }
}

Context::~Context() { destroy(); }

void Context::destroy() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    if (pool_) vkDestroyCommandPool(device_, pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  if (messenger_) {
    auto destroy_messenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy_messenger) destroy_messenger(instance_, messenger_, nullptr);
  }
  if (instance_) destroy_instance(instance_);
  device_ = VK_NULL_HANDLE;
  pool_ = VK_NULL_HANDLE;
  messenger_ = VK_NULL_HANDLE;
  instance_ = VK_NULL_HANDLE;
}

uint32_t Context::memory_type(uint32_t type_bits, VkMemoryPropertyFlags want) const {
  for (uint32_t i = 0; i < mem_props_.memoryTypeCount; ++i)
    if ((type_bits & (1u << i)) && (mem_props_.memoryTypes[i].propertyFlags & want) == want) return i;
  return UINT32_MAX;
}

std::vector<std::string> Context::validation_messages() const {
  std::lock_guard lock(messages_mutex_);
  return messages_;
}

VKAPI_ATTR VkBool32 VKAPI_CALL Context::on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                   VkDebugUtilsMessageTypeFlagsEXT,
                                                   const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  auto* self = static_cast<Context*>(user);
  std::lock_guard lock(self->messages_mutex_);
  self->messages_.push_back(std::string(severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error: " : "warning: ") +
                            (data && data->pMessage ? data->pMessage : "(no message)"));
  return VK_FALSE;
}

}  // namespace mpumesh::vk
