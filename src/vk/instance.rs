//! The Vulkan instance, and the validation layer's messenger that counts what it reports.

use std::ffi::{c_void, CStr, CString};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Mutex;

use anyhow::{bail, Context, Result};
use ash::{ext, vk};

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// What to do when the loader finds no driver, or no driver finds a device.
pub const NO_DRIVER: &str = "no Vulkan driver found: install one for your GPU, or Mesa's software \
     driver lavapipe (Debian/Ubuntu: `sudo apt install mesa-vulkan-drivers`, or `make setup`), \
     and check that VK_ICD_FILENAMES / VK_DRIVER_FILES, if set, name its JSON file";

/// How each validation message starts on stderr, so a parent process can count them.
pub const VALIDATION_PREFIX: &str = "vulkan validation: ";

/// Errors and warnings reported by the validation layer, kept so a caller (a test, a
/// `render` run) can fail when its own work produced one.
#[derive(Default)]
pub struct ValidationReport {
    errors: AtomicU32,
    warnings: AtomicU32,
    messages: Mutex<Vec<String>>,
}

impl ValidationReport {
    /// How many errors the layer has reported so far.
    pub fn error_count(&self) -> u32 {
        self.errors.load(Ordering::SeqCst)
    }

    pub fn warning_count(&self) -> u32 {
        self.warnings.load(Ordering::SeqCst)
    }

    /// Error and warning messages reported since `first` (an index into the full list).
    pub fn messages_since(&self, first: usize) -> Vec<String> {
        let messages = self.messages.lock().unwrap_or_else(|e| e.into_inner());
        messages.get(first..).map(<[String]>::to_vec).unwrap_or_default()
    }

    pub fn message_count(&self) -> usize {
        self.messages.lock().unwrap_or_else(|e| e.into_inner()).len()
    }

    fn record(&self, severity: vk::DebugUtilsMessageSeverityFlagsEXT, text: String) {
        if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
            self.errors.fetch_add(1, Ordering::SeqCst);
        } else {
            self.warnings.fetch_add(1, Ordering::SeqCst);
        }
        eprintln!("{VALIDATION_PREFIX}{text}");
        self.messages.lock().unwrap_or_else(|e| e.into_inner()).push(text);
    }
}

unsafe extern "system" fn on_validation_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _kind: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: the layer passes valid callback data; `user` is the `ValidationReport` boxed in
    // `Messenger`, which outlives the messenger that calls us.
    let report = &*(user as *const ValidationReport);
    let text = if data.is_null() || (*data).p_message.is_null() {
        String::from("(no message)")
    } else {
        CStr::from_ptr((*data).p_message).to_string_lossy().into_owned()
    };
    report.record(severity, text);
    vk::FALSE
}

struct Messenger {
    loader: ext::debug_utils::Instance,
    handle: vk::DebugUtilsMessengerEXT,
    report: Box<ValidationReport>,
}

/// Owns the loader entry, the instance and (when validation is on) the messenger.
pub struct Instance {
    pub entry: ash::Entry,
    pub handle: ash::Instance,
    messenger: Option<Messenger>,
}

/// Whether the validation layer should be on: always in debug builds, and whenever
/// `ARGIL_VALIDATION=1` (the tests set it).
pub fn validation_requested() -> bool {
    match std::env::var("ARGIL_VALIDATION") {
        Ok(v) => v != "0",
        Err(_) => cfg!(debug_assertions),
    }
}

impl Instance {
    /// `surface_extensions` are those a window needs (empty when rendering offscreen).
    pub fn new(validation: bool, surface_extensions: &[*const std::ffi::c_char]) -> Result<Self> {
        // SAFETY: loading the system Vulkan loader; failure is reported, not assumed.
        let entry = unsafe { ash::Entry::load() }
            .context("cannot load the Vulkan loader libvulkan.so.1: install it (Debian/Ubuntu: `sudo apt install libvulkan1`, or `make setup`)")?;
        let version = unsafe { entry.try_enumerate_instance_version() }?.unwrap_or(vk::API_VERSION_1_0);
        if version < vk::API_VERSION_1_3 {
            bail!(
                "the Vulkan loader supports {}.{}, argil needs 1.3",
                vk::api_version_major(version),
                vk::api_version_minor(version)
            );
        }

        let mut layers = Vec::new();
        let mut extensions: Vec<*const std::ffi::c_char> = surface_extensions.to_vec();
        if validation {
            let available = unsafe { entry.enumerate_instance_layer_properties() }?;
            let present = available
                .iter()
                .any(|l| l.layer_name_as_c_str().is_ok_and(|n| n == VALIDATION_LAYER));
            if !present {
                bail!("validation was requested but VK_LAYER_KHRONOS_validation is not installed (Debian: vulkan-validationlayers)");
            }
            layers.push(VALIDATION_LAYER.as_ptr());
            extensions.push(ext::debug_utils::NAME.as_ptr());
        }

        let app_name = CString::new("argil").expect("static name has no NUL");
        let app_info = vk::ApplicationInfo::default()
            .application_name(&app_name)
            .application_version(vk::make_api_version(0, 0, 1, 0))
            .engine_name(&app_name)
            .api_version(vk::API_VERSION_1_3);

        let mut severity =
            vk::DebugUtilsMessageSeverityFlagsEXT::ERROR | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING;
        if std::env::var_os("ARGIL_VALIDATION_VERBOSE").is_some() {
            severity |= vk::DebugUtilsMessageSeverityFlagsEXT::INFO;
        }
        let report = Box::new(ValidationReport::default());
        let mut messenger_info = vk::DebugUtilsMessengerCreateInfoEXT::default()
            .message_severity(severity)
            .message_type(
                vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                    | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                    | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
            )
            .pfn_user_callback(Some(on_validation_message))
            .user_data(&*report as *const ValidationReport as *mut c_void);
        // Synchronization validation catches missing barriers, which lavapipe would
        // otherwise forgive and a real GPU would not.
        let enabled_features = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        let mut validation_features =
            vk::ValidationFeaturesEXT::default().enabled_validation_features(&enabled_features);

        let mut create_info = vk::InstanceCreateInfo::default()
            .application_info(&app_info)
            .enabled_layer_names(&layers)
            .enabled_extension_names(&extensions);
        if validation {
            create_info = create_info
                .push_next(&mut messenger_info)
                .push_next(&mut validation_features);
        }
        let handle = match unsafe { entry.create_instance(&create_info, None) } {
            Ok(handle) => handle,
            Err(vk::Result::ERROR_INCOMPATIBLE_DRIVER) => bail!(NO_DRIVER),
            Err(e) => return Err(e).context("vkCreateInstance failed"),
        };

        let messenger = if validation {
            let loader = ext::debug_utils::Instance::new(&entry, &handle);
            match unsafe { loader.create_debug_utils_messenger(&messenger_info, None) } {
                Ok(h) => Some(Messenger {
                    loader,
                    handle: h,
                    report,
                }),
                Err(e) => {
                    unsafe { handle.destroy_instance(None) };
                    return Err(e).context("cannot create the debug messenger");
                }
            }
        } else {
            None
        };
        Ok(Self {
            entry,
            handle,
            messenger,
        })
    }

    /// The validation report, when validation is on.
    pub fn validation(&self) -> Option<&ValidationReport> {
        self.messenger.as_ref().map(|m| &*m.report)
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        unsafe {
            if let Some(m) = self.messenger.take() {
                m.loader.destroy_debug_utils_messenger(m.handle, None);
            }
            self.handle.destroy_instance(None);
        }
    }
}
