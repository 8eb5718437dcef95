//! Fault injection, to test that argil fails cleanly where a machine would fail it:
//! `ARGIL_FAULT` lists faults as `KIND:N`, comma-separated.
//!
//! - `alloc:N`: the N-th GPU memory allocation through a device's allocator fails as out
//!   of memory.
//! - `submit:N`: the N-th queue submission fails with `VK_ERROR_OUT_OF_DEVICE_MEMORY`.
//! - `device-lost:N`: the N-th submission fails with `VK_ERROR_DEVICE_LOST`, and so does
//!   every later submission, present, fence wait and idle wait on that device, as on a
//!   device that is really lost.
//! - `present:N`: the N-th present reports the swapchain out of date
//!   (`VK_ERROR_OUT_OF_DATE_KHR`), as when a window system takes it away; the viewer
//!   recreates it and goes on.
//! - `write:N`: every file written through [`crate::atomic`] fails after its first N
//!   bytes, as on a full disk.
//! - `panic:N`: the N-th queue submission panics, as a bug in argil would.
//!
//! Devices read it once, when they are created, and count in themselves; nothing here is
//! global or mutable.

use crate::error::InputError;

/// The variable's name.
pub const VARIABLE: &str = "ARGIL_FAULT";

/// Which operations fail, by their 1-based count.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Faults {
    pub alloc: Option<u64>,
    pub submit: Option<u64>,
    pub device_lost: Option<u64>,
    pub present: Option<u64>,
    /// Bytes a file write gets through before it fails.
    pub write: Option<u64>,
    pub panic: Option<u64>,
}

impl Faults {
    /// The faults `ARGIL_FAULT` asks for (none when it is unset or empty).
    pub fn from_env() -> Result<Self, InputError> {
        match std::env::var(VARIABLE) {
            Ok(spec) => Self::parse(&spec),
            Err(std::env::VarError::NotPresent) => Ok(Self::default()),
            Err(std::env::VarError::NotUnicode(_)) => Err(InputError(format!("{VARIABLE}: not UTF-8"))),
        }
    }

    pub fn parse(spec: &str) -> Result<Self, InputError> {
        let mut faults = Self::default();
        for item in spec.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let bad = |why: &str| {
                InputError(format!(
                    "{VARIABLE}={spec}: {item:?} {why}; \
                     expected alloc:N, submit:N, device-lost:N, present:N, write:N or panic:N"
                ))
            };
            let (kind, count) = item.split_once(':').ok_or_else(|| bad("has no count"))?;
            let count: u64 = count
                .parse()
                .map_err(|_| bad("has a count that is not a whole number"))?;
            let slot = match kind {
                "alloc" => &mut faults.alloc,
                "submit" => &mut faults.submit,
                "device-lost" => &mut faults.device_lost,
                "present" => &mut faults.present,
                "write" => &mut faults.write,
                "panic" => &mut faults.panic,
                _ => return Err(bad("is not a fault")),
            };
            if kind != "write" && count == 0 {
                return Err(bad("counts from 1"));
            }
            *slot = Some(count);
        }
        Ok(faults)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_kind_and_refuses_the_rest() {
        assert_eq!(Faults::parse("").unwrap(), Faults::default());
        assert_eq!(
            Faults::parse("alloc:3, submit:1,device-lost:7,present:2,write:0,panic:9").unwrap(),
            Faults {
                alloc: Some(3),
                submit: Some(1),
                device_lost: Some(7),
                present: Some(2),
                write: Some(0),
                panic: Some(9),
            }
        );
        for bad in ["alloc", "alloc:x", "alloc:0", "oom:3", "submit:-1"] {
            let error = Faults::parse(bad).unwrap_err().to_string();
            assert!(error.contains(bad) && error.contains("expected"), "{error}");
        }
    }
}
