//! Physical device choice, the logical device, its queue and the memory allocator.

use std::mem::ManuallyDrop;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard};

use anyhow::{anyhow, bail, Context, Result};
use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, Allocator, AllocatorCreateDesc};
use gpu_allocator::AllocationError;

use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

use super::instance::{Instance, ValidationReport};
use super::pipeline_cache::PipelineCache;
use super::surface::Surface;
use crate::cache::DiskCache;
use crate::error::InputError;
use crate::fault::Faults;

/// Which device to use, from `--device N|NAME`.
#[derive(Clone, Debug)]
pub enum DeviceChoice {
    /// The best by type: discrete GPU, then integrated, then virtual, then CPU.
    Best,
    /// An index into [`list_devices`].
    Index(usize),
    /// A case-insensitive part of the device name.
    Name(String),
}

impl std::str::FromStr for DeviceChoice {
    type Err = std::convert::Infallible;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Ok(match s.parse::<usize>() {
            Ok(i) => DeviceChoice::Index(i),
            Err(_) => DeviceChoice::Name(s.to_owned()),
        })
    }
}

/// What `argil devices` prints about one physical device.
#[derive(Clone, Debug)]
pub struct DeviceInfo {
    pub index: usize,
    pub name: String,
    pub kind: vk::PhysicalDeviceType,
    pub api_version: u32,
    pub driver: String,
    /// Why the device cannot run argil, if it cannot.
    pub unsupported: Option<String>,
}

impl std::fmt::Display for DeviceInfo {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let kind = match self.kind {
            vk::PhysicalDeviceType::DISCRETE_GPU => "discrete GPU",
            vk::PhysicalDeviceType::INTEGRATED_GPU => "integrated GPU",
            vk::PhysicalDeviceType::VIRTUAL_GPU => "virtual GPU",
            vk::PhysicalDeviceType::CPU => "CPU",
            _ => "other",
        };
        write!(
            f,
            "{}: {} ({kind}, Vulkan {}.{}.{}, {})",
            self.index,
            self.name,
            vk::api_version_major(self.api_version),
            vk::api_version_minor(self.api_version),
            vk::api_version_patch(self.api_version),
            self.driver
        )?;
        if let Some(why) = &self.unsupported {
            write!(f, " — unsupported: {why}")?;
        }
        Ok(())
    }
}

fn type_rank(kind: vk::PhysicalDeviceType) -> u32 {
    match kind {
        vk::PhysicalDeviceType::DISCRETE_GPU => 0,
        vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
        vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
        vk::PhysicalDeviceType::CPU => 3,
        _ => 4,
    }
}

/// The first queue family that does graphics and compute (and presents, if asked).
fn pick_queue_family(
    instance: &Instance,
    physical: vk::PhysicalDevice,
    present: Option<&dyn Fn(vk::PhysicalDevice, u32) -> bool>,
) -> Option<u32> {
    let families = unsafe { instance.handle.get_physical_device_queue_family_properties(physical) };
    families.iter().enumerate().find_map(|(i, f)| {
        let i = i as u32;
        let flags = vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE;
        let ok = f.queue_flags.contains(flags) && present.is_none_or(|p| p(physical, i));
        ok.then_some(i)
    })
}

fn describe(instance: &Instance, index: usize, physical: vk::PhysicalDevice) -> DeviceInfo {
    let mut driver = vk::PhysicalDeviceDriverProperties::default();
    let mut props2 = vk::PhysicalDeviceProperties2::default().push_next(&mut driver);
    unsafe { instance.handle.get_physical_device_properties2(physical, &mut props2) };
    let props = props2.properties;
    let name = props
        .device_name_as_c_str()
        .map_or_else(|_| "?".into(), |n| n.to_string_lossy().into_owned());
    let driver_name = driver
        .driver_info_as_c_str()
        .map_or_else(|_| String::new(), |n| n.to_string_lossy().into_owned());

    let mut v13 = vk::PhysicalDeviceVulkan13Features::default();
    let mut features = vk::PhysicalDeviceFeatures2::default().push_next(&mut v13);
    unsafe { instance.handle.get_physical_device_features2(physical, &mut features) };
    let unsupported = if props.api_version < vk::API_VERSION_1_3 {
        Some("needs Vulkan 1.3".to_owned())
    } else if v13.dynamic_rendering == vk::FALSE || v13.synchronization2 == vk::FALSE {
        Some("needs dynamic rendering and synchronization2".to_owned())
    } else if pick_queue_family(instance, physical, None).is_none() {
        Some("no graphics+compute queue".to_owned())
    } else {
        None
    };
    DeviceInfo {
        index,
        name,
        kind: props.device_type,
        api_version: props.api_version,
        driver: driver_name,
        unsupported,
    }
}

fn enumerate(instance: &Instance) -> Result<Vec<(vk::PhysicalDevice, DeviceInfo)>> {
    let physicals =
        unsafe { instance.handle.enumerate_physical_devices() }.context("cannot enumerate Vulkan devices")?;
    Ok(physicals
        .into_iter()
        .enumerate()
        .map(|(i, p)| (p, describe(instance, i, p)))
        .collect())
}

/// Every Vulkan device on this machine, in the loader's order.
pub fn list_devices() -> Result<Vec<DeviceInfo>> {
    let instance = Instance::new(false, &[])?;
    Ok(enumerate(&instance)?.into_iter().map(|(_, info)| info).collect())
}

/// Options for [`Device::new`].
pub struct DeviceOptions {
    pub choice: DeviceChoice,
    pub validation: bool,
}

/// The window a device will present to: its raw handles, for the surface.
#[derive(Clone, Copy)]
pub struct WindowHandles {
    pub display: RawDisplayHandle,
    pub window: RawWindowHandle,
}

/// The logical device and everything that lives exactly as long as it: the instance, the
/// queue and the allocator. Resources hold an `Arc<Device>`, so the device dies last.
pub struct Device {
    pub handle: ash::Device,
    pub physical: vk::PhysicalDevice,
    pub queue: vk::Queue,
    pub queue_family: u32,
    pub info: DeviceInfo,
    pub limits: vk::PhysicalDeviceLimits,
    /// Nanoseconds per timestamp tick; `None` when the queue has no timestamps.
    pub timestamp_period_ns: Option<f64>,
    pub max_anisotropy: Option<f32>,
    /// Every pipeline is created through it; written to the disk cache when the device goes.
    pub pipeline_cache: PipelineCache,
    allocator: ManuallyDrop<Mutex<Allocator>>,
    /// The queue must be externally synchronised: submissions, presents and waits for idle.
    queue_lock: Mutex<()>,
    /// `ARGIL_FAULT` as it was when the device was created, and what it counts.
    faults: Faults,
    allocations: AtomicU64,
    submissions: AtomicU64,
    presents: AtomicU64,
    /// Set by an injected `device-lost`: from then on the device answers as a lost one.
    lost: AtomicBool,
    /// The window surface this device presents to. Fields drop in order: the surface after
    /// the device, the instance last.
    pub surface: Option<Surface>,
    pub instance: Instance,
}

impl Device {
    /// Creates the device; with a window, also its surface, and picks a queue that can
    /// present to it.
    pub fn new(options: DeviceOptions, window: Option<WindowHandles>) -> Result<Self> {
        let faults = Faults::from_env()?;
        let surface_extensions = match window {
            Some(w) => ash_window::enumerate_required_extensions(w.display)
                .context("this window system has no Vulkan surface support")?
                .to_vec(),
            None => Vec::new(),
        };
        let instance = Instance::new(options.validation, &surface_extensions)?;
        let surface = window.map(|w| Surface::new(&instance, w)).transpose()?;
        let present_check = surface
            .as_ref()
            .map(|s| move |p: vk::PhysicalDevice, family: u32| s.supports(p, family));
        let present: Option<&dyn Fn(vk::PhysicalDevice, u32) -> bool> = present_check
            .as_ref()
            .map(|f| f as &dyn Fn(vk::PhysicalDevice, u32) -> bool);
        let candidates = enumerate(&instance)?;
        if candidates.is_empty() {
            bail!(super::instance::NO_DRIVER);
        }
        let usable = |info: &DeviceInfo, p: vk::PhysicalDevice| {
            info.unsupported.is_none() && pick_queue_family(&instance, p, present).is_some()
        };
        let (physical, info) = match &options.choice {
            DeviceChoice::Best => candidates
                .iter()
                .filter(|(p, info)| usable(info, *p))
                .min_by_key(|(_, info)| (type_rank(info.kind), info.index))
                .cloned()
                .ok_or_else(|| anyhow!("no Vulkan device supports argil: {}", list(&candidates)))?,
            DeviceChoice::Index(i) => candidates
                .get(*i)
                .cloned()
                .ok_or_else(|| InputError(format!("--device {i}: no such device; devices: {}", list(&candidates))))?,
            DeviceChoice::Name(name) => {
                let lower = name.to_lowercase();
                candidates
                    .iter()
                    .find(|(_, info)| info.name.to_lowercase().contains(&lower))
                    .cloned()
                    .ok_or_else(|| {
                        InputError(format!(
                            "--device {name}: no device has that in its name; devices: {}",
                            list(&candidates)
                        ))
                    })?
            }
        };
        if let Some(why) = &info.unsupported {
            bail!("device {} cannot run argil: {why}", info.name);
        }
        let queue_family = pick_queue_family(&instance, physical, present)
            .ok_or_else(|| anyhow!("device {} has no queue that can draw and present", info.name))?;

        let props = unsafe { instance.handle.get_physical_device_properties(physical) };
        let supported = unsafe { instance.handle.get_physical_device_features(physical) };
        let families = unsafe { instance.handle.get_physical_device_queue_family_properties(physical) };
        let timestamp_period_ns = (families[queue_family as usize].timestamp_valid_bits > 0
            && props.limits.timestamp_period > 0.0)
            .then_some(f64::from(props.limits.timestamp_period));
        // Software rasterisers advertise anisotropic filtering but pay for it per sample:
        // lavapipe (Mesa 22.3) takes minutes for one 160×90 frame of a normal-mapped sphere
        // with 16x, against half a second without. GPUs filter it in hardware.
        let max_anisotropy = (supported.sampler_anisotropy == vk::TRUE
            && props.device_type != vk::PhysicalDeviceType::CPU)
            .then_some(props.limits.max_sampler_anisotropy);

        let priorities = [1.0f32];
        let queue_infos = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&priorities)];
        let features = vk::PhysicalDeviceFeatures::default().sampler_anisotropy(max_anisotropy.is_some());
        let mut supported13 = vk::PhysicalDeviceVulkan13Features::default();
        let mut supported2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut supported13);
        unsafe { instance.handle.get_physical_device_features2(physical, &mut supported2) };
        // maintenance4 lets a vertex shader write outputs that a fragment shader ignores
        // (debug views read them, plain shading does not) without a performance warning.
        let mut v13 = vk::PhysicalDeviceVulkan13Features::default()
            .dynamic_rendering(true)
            .synchronization2(true)
            .maintenance4(supported13.maintenance4 == vk::TRUE);
        let mut extensions: Vec<*const std::ffi::c_char> = Vec::new();
        if present.is_some() {
            extensions.push(ash::khr::swapchain::NAME.as_ptr());
        }
        let create_info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queue_infos)
            .enabled_features(&features)
            .enabled_extension_names(&extensions)
            .push_next(&mut v13);
        let handle = unsafe { instance.handle.create_device(physical, &create_info, None) }
            .with_context(|| format!("cannot create a logical device on {}", info.name))?;
        let queue = unsafe { handle.get_device_queue(queue_family, 0) };

        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.handle.clone(),
            device: handle.clone(),
            physical_device: physical,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        });
        let allocator = match allocator {
            Ok(a) => a,
            Err(e) => {
                unsafe { handle.destroy_device(None) };
                return Err(e).context("cannot create the GPU memory allocator");
            }
        };
        let pipeline_cache = match PipelineCache::new(&handle, &props, DiskCache::from_env()) {
            Ok(cache) => cache,
            Err(e) => {
                drop(allocator);
                unsafe { handle.destroy_device(None) };
                return Err(e);
            }
        };

        Ok(Self {
            handle,
            physical,
            queue,
            queue_family,
            info,
            limits: props.limits,
            timestamp_period_ns,
            max_anisotropy,
            pipeline_cache,
            allocator: ManuallyDrop::new(Mutex::new(allocator)),
            queue_lock: Mutex::new(()),
            faults,
            allocations: AtomicU64::new(0),
            submissions: AtomicU64::new(0),
            presents: AtomicU64::new(0),
            lost: AtomicBool::new(false),
            surface,
            instance,
        })
    }

    pub fn allocator(&self) -> MutexGuard<'_, Allocator> {
        self.allocator.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Allocates memory from the device's allocator (or fails, as `ARGIL_FAULT=alloc:N` asks).
    pub fn allocate(&self, desc: &AllocationCreateDesc<'_>) -> Result<Allocation, AllocationError> {
        let n = self.allocations.fetch_add(1, Ordering::SeqCst) + 1;
        if self.faults.alloc == Some(n) {
            return Err(AllocationError::OutOfMemory);
        }
        self.allocator().allocate(desc)
    }

    /// `VK_ERROR_DEVICE_LOST` once an injected loss has happened.
    pub fn check_lost(&self) -> std::result::Result<(), vk::Result> {
        if self.lost.load(Ordering::SeqCst) {
            return Err(vk::Result::ERROR_DEVICE_LOST);
        }
        Ok(())
    }

    /// Submits to the device's one queue.
    pub fn submit(&self, submits: &[vk::SubmitInfo2<'_>], fence: vk::Fence) -> Result<()> {
        let n = self.submissions.fetch_add(1, Ordering::SeqCst) + 1;
        assert!(self.faults.panic != Some(n), "{}=panic:{n}", crate::fault::VARIABLE);
        if self.faults.device_lost == Some(n) {
            self.lost.store(true, Ordering::SeqCst);
        }
        let injected = if self.faults.submit == Some(n) {
            Err(vk::Result::ERROR_OUT_OF_DEVICE_MEMORY)
        } else {
            self.check_lost()
        };
        let _guard = self.queue_lock.lock().unwrap_or_else(|e| e.into_inner());
        injected
            .and_then(|()| unsafe { self.handle.queue_submit2(self.queue, submits, fence) })
            .context("vkQueueSubmit2 failed")
    }

    /// Presents on the device's queue (which was chosen to support presenting).
    pub fn present(
        &self,
        loader: &ash::khr::swapchain::Device,
        info: &vk::PresentInfoKHR<'_>,
    ) -> std::result::Result<bool, vk::Result> {
        self.check_lost()?;
        let _guard = self.queue_lock.lock().unwrap_or_else(|e| e.into_inner());
        let presented = unsafe { loader.queue_present(self.queue, info) };
        // After the real present, so its semaphore waits happen as they would.
        if self.faults.present == Some(self.presents.fetch_add(1, Ordering::SeqCst) + 1) {
            return Err(vk::Result::ERROR_OUT_OF_DATE_KHR);
        }
        presented
    }

    /// Waits until the queue is idle. vkDeviceWaitIdle uses the queue, so it holds the
    /// queue's lock: a submission from another thread waits for it.
    pub fn wait_idle(&self) -> Result<()> {
        let _guard = self.queue_lock.lock().unwrap_or_else(|e| e.into_inner());
        // The real wait even after an injected loss: work submitted before it is still
        // running, and the caller is about to destroy what it uses.
        let waited = unsafe { self.handle.device_wait_idle() };
        self.check_lost().and(waited).context("vkDeviceWaitIdle failed")
    }

    /// The validation layer's report, when validation is on.
    pub fn validation(&self) -> Option<&ValidationReport> {
        self.instance.validation()
    }

    /// Names a Vulkan object for validation messages and debuggers.
    pub fn set_name<H: vk::Handle>(&self, handle: H, name: &str) {
        if self.instance.validation().is_none() {
            return;
        }
        let Ok(name) = std::ffi::CString::new(name) else { return };
        let loader = ash::ext::debug_utils::Device::new(&self.instance.handle, &self.handle);
        let info = vk::DebugUtilsObjectNameInfoEXT::default()
            .object_handle(handle)
            .object_name(&name);
        // Naming is a debugging aid; failing to name is not an error worth stopping for.
        let _ = unsafe { loader.set_debug_utils_object_name(&info) };
    }
}

fn list(candidates: &[(vk::PhysicalDevice, DeviceInfo)]) -> String {
    candidates
        .iter()
        .map(|(_, i)| i.to_string())
        .collect::<Vec<_>>()
        .join("; ")
}

impl Drop for Device {
    fn drop(&mut self) {
        unsafe {
            let _ = self.handle.device_wait_idle();
            self.pipeline_cache.save_and_destroy(&self.handle);
            // The allocator frees its memory blocks through the device, so it goes first.
            ManuallyDrop::drop(&mut self.allocator);
            self.handle.destroy_device(None);
        }
    }
}
