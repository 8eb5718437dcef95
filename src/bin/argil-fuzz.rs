//! `argil-fuzz`: mutates the seed corpus of every loader for a given time and keeps what
//! crashes. An input is a crasher when its loader panics, or takes longer than
//! `--slow-seconds`; a watchdog writes an input that hangs for `--hang-seconds` and stops.
//! A mutant whose error message (numbers aside) is new joins the pool it mutates from, so
//! the run reaches past the first check of each format. Crashers go to
//! `tests/fuzz/crashers/TARGET/`, which `tests/fuzz.rs` replays.
//!
//! `cargo run --release --bin argil-fuzz -- --seconds 1800`

use std::collections::{HashMap, HashSet};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use clap::Parser;

use argil::fuzz::{crasher_name, read_corpus, signature, Harness, Mutator, Target};

#[derive(Parser)]
#[command(
    name = "argil-fuzz",
    about = "Mutate argil's loaders' seed corpus and keep what crashes"
)]
struct Args {
    /// How long to run.
    #[arg(long, default_value_t = 60.0)]
    seconds: f64,
    /// Seed of the mutations [default: from the clock].
    #[arg(long)]
    seed: Option<u64>,
    /// Targets, comma-separated: scene, obj, png, jpeg, hdr, exr [default: all].
    #[arg(long, value_delimiter = ',')]
    targets: Vec<String>,
    /// The seed corpus: one folder per target, and `assets/` for the files scenes name.
    #[arg(long, default_value = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fuzz/corpus"))]
    corpus: PathBuf,
    /// Where crashers are written, one folder per target.
    #[arg(long, default_value = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fuzz/crashers"))]
    crashers: PathBuf,
    /// An input slower than this is a crasher.
    #[arg(long, default_value_t = 5.0)]
    slow_seconds: f64,
    /// An input still running after this long is written out and the run stops (exit 3).
    #[arg(long, default_value_t = 120.0)]
    hang_seconds: f64,
}

/// Mutants of one target, seeds first; capped so the pool stays mostly near the seeds.
const MAX_POOL: usize = 2000;
/// Mutants larger than this do not join the pool.
const MAX_POOL_INPUT: usize = 1 << 16;

/// The input being run, for the watchdog.
struct Current {
    target: Target,
    input: Vec<u8>,
    started: Instant,
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_owned())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "(a panic without a message)".to_owned())
}

fn write_crasher(dir: &Path, target: Target, input: &[u8]) -> Result<PathBuf> {
    let dir = dir.join(target.name());
    std::fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let path = dir.join(crasher_name(target, input));
    argil::atomic::write_bytes(&path, argil::atomic::Existing::Replace, input)?;
    Ok(path)
}

#[derive(Default)]
struct Stats {
    runs: u64,
    accepted: u64,
    signatures: HashSet<String>,
    crashes: HashSet<String>,
}

fn main() -> Result<()> {
    let args = Args::parse();
    let targets: Vec<Target> = if args.targets.is_empty() {
        Target::ALL.to_vec()
    } else {
        args.targets
            .iter()
            .map(|name| Target::from_name(name).with_context(|| format!("no target {name:?}")))
            .collect::<Result<_>>()?
    };
    let seed = args.seed.unwrap_or_else(|| {
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(1, |d| d.as_nanos() as u64)
    });
    let scratch = std::env::temp_dir().join(format!("argil-fuzz-{}", std::process::id()));
    let harness = Harness::new(&scratch, &args.corpus.join("assets"))?;
    let mut pools: HashMap<Target, Vec<Vec<u8>>> = HashMap::new();
    let mut seeds: HashMap<Target, usize> = HashMap::new();
    for &target in &targets {
        let corpus: Vec<Vec<u8>> = read_corpus(&args.corpus.join(target.name()))?
            .into_iter()
            .map(|(_, bytes)| bytes)
            .collect();
        if corpus.is_empty() {
            bail!("no seeds in {}", args.corpus.join(target.name()).display());
        }
        seeds.insert(target, corpus.len());
        pools.insert(target, corpus);
    }
    eprintln!(
        "argil-fuzz: seed {seed}, {:.0} s, targets {}, inputs in {}",
        args.seconds,
        targets.iter().map(|t| t.name()).collect::<Vec<_>>().join(","),
        scratch.display()
    );

    let current: Arc<Mutex<Option<Current>>> = Arc::new(Mutex::new(None));
    let watchdog = {
        let current = current.clone();
        let crashers = args.crashers.clone();
        let hang = Duration::from_secs_f64(args.hang_seconds);
        move || loop {
            std::thread::sleep(Duration::from_secs(1));
            if let Some(c) = lock(&current).as_ref().filter(|c| c.started.elapsed() > hang) {
                match write_crasher(&crashers, c.target, &c.input) {
                    Ok(path) => eprintln!("argil-fuzz: HANG over {hang:?}: {}", path.display()),
                    Err(e) => eprintln!("argil-fuzz: HANG over {hang:?}, and {e:#}"),
                }
                std::process::exit(3);
            }
        }
    };
    std::thread::spawn(watchdog);
    // Panics are expected findings, reported with their input; the default hook would
    // print each one's backtrace line between the reports.
    std::panic::set_hook(Box::new(|_| {}));

    let mut mutator = Mutator::new(seed);
    let mut stats: HashMap<Target, Stats> = targets.iter().map(|&t| (t, Stats::default())).collect();
    let start = Instant::now();
    let deadline = Duration::from_secs_f64(args.seconds);
    let mut next_report = Duration::from_secs(60);
    let mut crashers = 0usize;
    'run: loop {
        for &target in &targets {
            if start.elapsed() >= deadline {
                break 'run;
            }
            let pool = &pools[&target];
            // Half the time a seed: the pool fills with broken inputs.
            let from = if mutator.below(2) == 0 {
                seeds[&target]
            } else {
                pool.len()
            };
            let input = &pool[mutator.below(from)];
            let other = &pool[mutator.below(pool.len())];
            let mutant = mutator.mutate(target, input, other);
            *lock(&current) = Some(Current {
                target,
                input: mutant.clone(),
                started: Instant::now(),
            });
            let began = Instant::now();
            let outcome = catch_unwind(AssertUnwindSafe(|| harness.run(target, &mutant)));
            let took = began.elapsed();
            *lock(&current) = None;
            let s = stats.get_mut(&target).context("stats of every target")?;
            s.runs += 1;
            let finding = match outcome {
                Err(payload) => Some(format!("panic: {}", panic_message(&*payload))),
                Ok(result) => {
                    let result = result?;
                    let key = match &result {
                        Ok(()) => {
                            s.accepted += 1;
                            "ok".to_owned()
                        }
                        Err(message) => signature(message),
                    };
                    let slow = took.as_secs_f64() > args.slow_seconds;
                    if s.signatures.insert(key) && mutant.len() <= MAX_POOL_INPUT && !slow {
                        let pool = pools.get_mut(&target).context("pool of every target")?;
                        if pool.len() < MAX_POOL {
                            pool.push(mutant.clone());
                        }
                    }
                    slow.then(|| format!("slow: {:.1} s", took.as_secs_f64()))
                }
            };
            if let Some(finding) = finding {
                if s.crashes.insert(signature(&finding)) {
                    let path = write_crasher(&args.crashers, target, &mutant)?;
                    crashers += 1;
                    eprintln!("argil-fuzz: {} {finding}: {}", target.name(), path.display());
                }
            }
        }
        if start.elapsed() >= next_report {
            next_report += Duration::from_secs(60);
            report(&start, &targets, &stats, &pools);
        }
    }
    report(&start, &targets, &stats, &pools);
    eprintln!("argil-fuzz: {crashers} new crasher(s)");
    let _ = std::fs::remove_dir_all(&scratch);
    Ok(())
}

fn report(start: &Instant, targets: &[Target], stats: &HashMap<Target, Stats>, pools: &HashMap<Target, Vec<Vec<u8>>>) {
    let rows: Vec<String> = targets
        .iter()
        .filter_map(|t| {
            let s = stats.get(t)?;
            Some(format!(
                "{} {} runs ({} accepted, {} behaviours, pool {}, {} crash kinds)",
                t.name(),
                s.runs,
                s.accepted,
                s.signatures.len(),
                pools.get(t).map_or(0, Vec::len),
                s.crashes.len()
            ))
        })
        .collect();
    eprintln!(
        "argil-fuzz: {:.0} s: {}",
        start.elapsed().as_secs_f64(),
        rows.join("; ")
    );
}
