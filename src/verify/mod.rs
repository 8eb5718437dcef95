//! `argil verify`: checks every BRDF model and term of `shaders/lib/brdf.glsl`, the display
//! transform of `tonemap.glsl`, normal mapping (`normal_mapping.glsl`) and the shading of
//! `shading.glsl`, and reports one table.
//!
//! 1. GPU against f64: `shaders/verify_brdf.comp` evaluates each function on random f32
//!    tuples over its whole domain; the f64 twins of `src/brdf` get the same tuples. Unit
//!    vectors also by the angle between the two.
//! 2. Positivity and range (unit length for normals) everywhere, Helmholtz reciprocity of the
//!    BRDFs (GPU and f64), and what a function promises besides: decoded normals above the
//!    surface, shading normals facing the viewer, the terminator shadowing continuous.
//! 3. Energy, by f64 quadrature: albedo, gains against the oracle, normalisation, furnace.
//! 4. Stress inputs (horizon, zero half vector, extreme α, degenerate normals and tangents,
//!    v = −n, denormals) on both sides: finite, non-negative and capped, or unit.

mod composite;
mod energy;
mod functions;
mod gpu;
mod normals;
mod sweep;
mod terms;

use std::fmt::Write as _;
use std::sync::Arc;
use std::time::Instant;

use anyhow::{anyhow, ensure, Result};

use crate::rng::Rng;
use crate::vk::Device;
use functions::{Function, Tuple};

/// Random tuples per function: the brief asks for at least 10⁶.
pub const DEFAULT_SAMPLES: usize = 1 << 20;
/// Seed of the random tuples: fixed, so every run checks the same inputs.
pub const DEFAULT_SEED: u64 = 0x0a76_1c1a_7b2d_f00d;

pub struct Options {
    pub samples: usize,
    pub seed: u64,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    Pass,
    Fail,
    /// A measured property the model is known not to have (an energy gain), matching its
    /// oracle.
    Reported,
    /// The check does not apply (reciprocity of what is not a BRDF).
    NotApplicable,
}

impl Status {
    fn label(self) -> &'static str {
        match self {
            Status::Pass => "pass",
            Status::Fail => "FAIL",
            Status::Reported => "reported",
            Status::NotApplicable => "n/a",
        }
    }
}

pub struct Row {
    pub model: String,
    pub check: String,
    pub measured: String,
    pub tolerance: String,
    pub status: Status,
    /// Where the worst case is, or why the tolerance is what it is.
    pub note: String,
}

pub struct Report {
    pub device: String,
    pub rows: Vec<Row>,
    pub seconds: f64,
}

impl Report {
    pub fn failures(&self) -> usize {
        self.rows.iter().filter(|r| r.status == Status::Fail).count()
    }

    /// The table in aligned plain-text columns; notes run past the last column.
    pub fn table(&self) -> String {
        let header = ["model", "check", "measured", "tolerance", "status"];
        fn cells(r: &Row) -> [&str; 5] {
            [&r.model, &r.check, &r.measured, &r.tolerance, r.status.label()]
        }
        let mut widths = header.map(|h| h.chars().count());
        for r in &self.rows {
            for (w, c) in widths.iter_mut().zip(cells(r)) {
                *w = (*w).max(c.chars().count());
            }
        }
        let line = |columns: [&str; 5], note: &str| {
            let mut s = String::new();
            for (c, w) in columns.iter().zip(widths) {
                let _ = write!(s, "{c}{}  ", " ".repeat(w - c.chars().count()));
            }
            s.push_str(note);
            s.trim_end().to_owned() + "\n"
        };
        let mut out = line(header, "note");
        out += &line(widths.map(|w| "-".repeat(w)).each_ref().map(String::as_str), "----");
        for r in &self.rows {
            out += &line(cells(r), &r.note);
        }
        let _ = writeln!(
            out,
            "\n{} checks on {}: {} pass, {} reported, {} n/a, {} FAIL; {:.1} s",
            self.rows.len(),
            self.device,
            self.count(Status::Pass),
            self.count(Status::Reported),
            self.count(Status::NotApplicable),
            self.failures(),
            self.seconds
        );
        out
    }

    fn count(&self, status: Status) -> usize {
        self.rows.iter().filter(|r| r.status == status).count()
    }

    /// The table as JSON: {"device", "seconds", "rows": [{model, check, …}]}.
    pub fn json(&self) -> String {
        let rows: Vec<String> = self
            .rows
            .iter()
            .map(|r| {
                format!(
                    "    {{\"model\": {}, \"check\": {}, \"measured\": {}, \"tolerance\": {}, \"status\": {}, \"note\": {}}}",
                    json_string(&r.model),
                    json_string(&r.check),
                    json_string(&r.measured),
                    json_string(&r.tolerance),
                    json_string(r.status.label()),
                    json_string(&r.note)
                )
            })
            .collect();
        format!(
            "{{\n  \"device\": {},\n  \"seconds\": {:.3},\n  \"failures\": {},\n  \"rows\": [\n{}\n  ]\n}}\n",
            json_string(&self.device),
            self.seconds,
            self.failures(),
            rows.join(",\n")
        )
    }
}

fn json_string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if u32::from(c) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", u32::from(c));
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// Runs every check on `device`.
pub fn run(device: &Arc<Device>, options: &Options) -> Result<Report> {
    ensure!(options.samples > 0, "--samples must be at least 1");
    let start = Instant::now();
    let mut rng = Rng::new(options.seed);
    let stress_max = Function::all().map(|f| f.stress().len()).max().unwrap_or(0);
    let mut harness = gpu::Harness::new(device, options.samples + stress_max)?;

    let functions: Vec<Function> = Function::all().collect();
    let draw = |function: Function, rng: &mut Rng, tuples: &mut Vec<Tuple>| {
        tuples.clear();
        tuples.extend((0..options.samples).map(|_| function.sample(rng)));
        tuples.extend(function.stress());
    };
    // Reused from function to function: fresh vectors of up to 100 MB each cost more in page
    // faults than anything else the CPU does here.
    let (mut tuples, mut next) = (Vec::new(), Vec::new());
    let (mut gpu, mut cpu) = (Vec::new(), Vec::new());
    let (swept, energy) = std::thread::scope(|scope| -> Result<_> {
        // f64 quadrature only: it fills the cores' idle moments.
        let energy = scope.spawn(energy::rows);
        let mut swept = Vec::new();
        if let Some(&first) = functions.first() {
            draw(first, &mut rng, &mut tuples);
        }
        for (k, &function) in functions.iter().enumerate() {
            // The f64 side runs on a CPU thread while the GPU (or lavapipe's threads) evaluates.
            let (evaluated, twins) = std::thread::scope(|scope| {
                let twins = scope.spawn(|| {
                    cpu.clear();
                    cpu.extend(tuples.iter().map(|t| function.eval(t)));
                });
                (harness.evaluate(function, &tuples, &mut gpu), twins.join())
            });
            twins.map_err(|_| anyhow!("the f64 evaluation of {} panicked", function.name()))?;
            evaluated?;
            // The next function's tuples are drawn while this one's rows are worked out: each
            // takes one core.
            let (own, drawn) = std::thread::scope(|scope| {
                let drawing = functions.get(k + 1).map(|&f| {
                    let (rng, next) = (&mut rng, &mut next);
                    scope.spawn(move || draw(f, rng, next))
                });
                let own = sweep::rows(function, &tuples, options.samples, &gpu, &cpu);
                (own, drawing.map(|h| h.join()))
            });
            drawn
                .transpose()
                .map_err(|_| anyhow!("drawing the tuples after {} panicked", function.name()))?;
            swept.push((function, own));
            std::mem::swap(&mut tuples, &mut next);
        }
        let energy = energy.join().map_err(|_| anyhow!("the energy quadrature panicked"))?;
        Ok((swept, energy))
    })?;
    // Each function's energy rows follow its own.
    let mut rows = Vec::new();
    let mut energy = energy;
    for (function, own) in swept {
        rows.extend(own);
        let (mine, rest): (Vec<Row>, Vec<Row>) = energy.into_iter().partition(|r| r.model == function.name());
        rows.extend(mine);
        energy = rest;
    }
    rows.extend(energy);
    Ok(Report {
        device: device.info.name.clone(),
        rows,
        seconds: start.elapsed().as_secs_f64(),
    })
}
