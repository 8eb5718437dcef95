//! Replays the fuzz corpus (`tests/fuzz/corpus/TARGET/`) and every crasher `argil-fuzz`
//! has found (`tests/fuzz/crashers/TARGET/`) through the loaders: none may panic or take
//! long, every seed must load (a seed that is rejected no longer reaches past the first
//! check), and a short fixed-seed mutation run must not panic either.

mod common;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::time::{Duration, Instant};

use argil::fuzz::{read_corpus, Harness, Mutator, Target};
use argil::scratch::Scratch;
use common::test_dir;

/// The slowest accepted input takes well under a second in a release build; this leaves
/// room for a machine busy with other builds.
const MAX_TIME: Duration = Duration::from_secs(20);

fn fuzz_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz")
}

/// A harness writing its inputs into a scratch folder removed with the returned `Scratch`.
fn harness(name: &str) -> (Scratch, Harness) {
    let scratch = test_dir(name);
    let harness = Harness::new(&scratch, &fuzz_dir().join("corpus/assets")).expect("scratch folder");
    (scratch, harness)
}

/// Runs `input`, returning the loader's verdict, or a description of a panic or a slow run.
fn run(harness: &Harness, target: Target, input: &[u8]) -> Result<Result<(), String>, String> {
    let began = Instant::now();
    let outcome = catch_unwind(AssertUnwindSafe(|| harness.run(target, input).expect("harness")));
    let took = began.elapsed();
    match outcome {
        Err(_) => Err("panicked".to_owned()),
        Ok(_) if took > MAX_TIME => Err(format!("took {took:?}")),
        Ok(verdict) => Ok(verdict),
    }
}

#[test]
fn every_seed_loads() {
    let (_scratch, harness) = harness("seeds");
    let mut problems = Vec::new();
    for target in Target::ALL {
        let seeds = read_corpus(&fuzz_dir().join("corpus").join(target.name())).expect("corpus");
        assert!(!seeds.is_empty(), "no seeds for {}", target.name());
        for (path, bytes) in seeds {
            match run(&harness, target, &bytes) {
                Ok(Ok(())) => {}
                Ok(Err(message)) => problems.push(format!("{}: rejected: {message}", path.display())),
                Err(problem) => problems.push(format!("{}: {problem}", path.display())),
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn every_crasher_is_rejected_or_loaded_without_a_panic() {
    let (_scratch, harness) = harness("crashers");
    let mut problems = Vec::new();
    let mut count = 0;
    for target in Target::ALL {
        for (path, bytes) in read_corpus(&fuzz_dir().join("crashers").join(target.name())).expect("crashers") {
            count += 1;
            if let Err(problem) = run(&harness, target, &bytes) {
                problems.push(format!("{}: {problem}", path.display()));
            }
        }
    }
    eprintln!("{count} crashers replayed");
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn a_short_mutation_run_finds_no_crash() {
    let (_scratch, harness) = harness("mutants");
    let mut mutator = Mutator::new(13);
    let mut problems = Vec::new();
    for target in Target::ALL {
        let seeds = read_corpus(&fuzz_dir().join("corpus").join(target.name())).expect("corpus");
        for _ in 0..100 {
            let input = &seeds[mutator.below(seeds.len())].1;
            let other = &seeds[mutator.below(seeds.len())].1;
            let mutant = mutator.mutate(target, input, other);
            if let Err(problem) = run(&harness, target, &mutant) {
                problems.push(format!(
                    "{} mutant {:?}: {problem}",
                    target.name(),
                    String::from_utf8_lossy(&mutant)
                ));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
