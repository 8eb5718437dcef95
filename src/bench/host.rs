//! The machine a run was made on. On a software device such as lavapipe the host's CPU is
//! the device, so its milliseconds compare only between rows of one host; the ratios to
//! the floor, measured in the same run, are what carries across machines.

/// The CPU's model name and the threads the process may run, e.g. "AMD EPYC 7B13, 2
/// threads"; "unknown CPU" where the system does not say.
pub fn describe() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|text| model_name(&text))
        .unwrap_or_else(|| "unknown CPU".to_owned());
    let threads = std::thread::available_parallelism().map_or(1, usize::from);
    format!("{cpu}, {threads} thread{}", if threads == 1 { "" } else { "s" })
}

/// The first `model name` of a Linux /proc/cpuinfo, its runs of spaces made one.
fn model_name(cpuinfo: &str) -> Option<String> {
    cpuinfo.lines().find_map(|line| {
        let (key, value) = line.split_once(':')?;
        let value = value.split_whitespace().collect::<Vec<_>>().join(" ");
        (key.trim() == "model name" && !value.is_empty()).then_some(value)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_model_name_is_the_first_one_its_spaces_made_one() {
        let cpuinfo = "processor\t: 0\nvendor_id\t: AuthenticAMD\nmodel name\t: AMD EPYC  7B13 64-Core Processor\n\
                       processor\t: 1\nmodel name\t: other\n";
        assert_eq!(model_name(cpuinfo).as_deref(), Some("AMD EPYC 7B13 64-Core Processor"));
        assert_eq!(model_name("processor\t: 0\nmodel name\t:   \n"), None);
        assert_eq!(model_name(""), None);
        assert!(describe().contains(" thread"), "{}", describe());
    }
}
