//! Frame timings for the UI: the CPU's work per frame and GPU milliseconds per pass,
//! averaged over the last second (not over a number of frames, which at lavapipe's rates
//! would span minutes), with a short history for the graph.

use std::collections::VecDeque;
use std::time::{Duration, Instant};

/// Means and the frame rate are over this much of the newest history.
pub const WINDOW: Duration = Duration::from_secs(1);

/// Frames kept for the graph.
pub const HISTORY: usize = 240;

/// One frame's times in milliseconds.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameTimes {
    /// When the frame started.
    pub at: Instant,
    /// What the CPU spent on the frame before submitting it: camera, UI, recording.
    pub cpu_ms: f64,
    /// Per pass, in the order of [`Timings::pass_names`]; empty without timestamps.
    pub gpu_ms: Vec<f64>,
}

impl FrameTimes {
    pub fn gpu_total_ms(&self) -> f64 {
        self.gpu_ms.iter().sum()
    }
}

pub struct Timings {
    pub pass_names: Vec<&'static str>,
    history: VecDeque<FrameTimes>,
}

impl Timings {
    pub fn new(pass_names: Vec<&'static str>) -> Self {
        Self {
            pass_names,
            history: VecDeque::with_capacity(HISTORY),
        }
    }

    pub fn push(&mut self, times: FrameTimes) {
        if self.history.len() == HISTORY {
            self.history.pop_front();
        }
        self.history.push_back(times);
    }

    /// Oldest first.
    pub fn history(&self) -> impl ExactSizeIterator<Item = &FrameTimes> {
        self.history.iter()
    }

    /// The frames of the last [`WINDOW`] before the newest, at least the newest.
    fn recent(&self) -> impl Iterator<Item = &FrameTimes> {
        let newest = self.history.back().map(|t| t.at);
        self.history
            .iter()
            .filter(move |t| newest.is_some_and(|n| n.duration_since(t.at) <= WINDOW))
    }

    /// Mean CPU work and mean GPU time of each pass over the last second; `None` before
    /// the first frame.
    pub fn mean(&self) -> Option<(f64, Vec<f64>)> {
        let n = self.recent().count();
        if n == 0 {
            return None;
        }
        let passes = self.recent().map(|t| t.gpu_ms.len()).max().unwrap_or(0);
        let mut gpu_ms = vec![0.0; passes];
        for t in self.recent() {
            for (sum, ms) in gpu_ms.iter_mut().zip(&t.gpu_ms) {
                *sum += ms / n as f64;
            }
        }
        Some((self.recent().map(|t| t.cpu_ms).sum::<f64>() / n as f64, gpu_ms))
    }

    /// Frames per second over the last second of frames; `None` with fewer than two.
    pub fn fps(&self) -> Option<f64> {
        let first = self.recent().next()?;
        let last = self.history.back()?;
        let n = self.recent().count();
        let span = last.at.duration_since(first.at).as_secs_f64();
        (n >= 2 && span > 0.0).then(|| (n - 1) as f64 / span)
    }

    /// The largest CPU or total GPU time in the history: the graph's scale.
    pub fn peak_ms(&self) -> f64 {
        self.history
            .iter()
            .map(|t| t.cpu_ms.max(t.gpu_total_ms()))
            .fold(0.0, f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn times(at: Instant, cpu: f64, gpu: &[f64]) -> FrameTimes {
        FrameTimes {
            at,
            cpu_ms: cpu,
            gpu_ms: gpu.to_vec(),
        }
    }

    #[test]
    fn history_is_bounded_and_keeps_the_newest() {
        let mut t = Timings::new(vec!["a"]);
        let t0 = Instant::now();
        for i in 0..HISTORY + 10 {
            t.push(times(t0, i as f64, &[1.0]));
        }
        assert_eq!(t.history().len(), HISTORY);
        assert_eq!(t.history().next().map(|f| f.cpu_ms), Some(10.0));
        assert_eq!(t.history().last().map(|f| f.cpu_ms), Some((HISTORY + 9) as f64));
    }

    #[test]
    fn means_and_rate_cover_the_last_second_and_peak_the_history() {
        let mut t = Timings::new(vec!["forward", "tonemap"]);
        assert_eq!(t.mean(), None);
        assert_eq!(t.fps(), None);
        assert_eq!(t.peak_ms(), 0.0);
        let t0 = Instant::now();
        let ms = |n: u64| t0 + Duration::from_millis(n);
        t.push(times(ms(0), 40.0, &[30.0, 1.0]));
        t.push(times(ms(1500), 10.0, &[2.0, 1.0]));
        t.push(times(ms(2000), 20.0, &[4.0, 3.0]));
        // The first frame is more than a second older than the newest: left out.
        assert_eq!(t.mean(), Some((15.0, vec![3.0, 2.0])));
        assert_eq!(t.fps(), Some(2.0));
        assert_eq!(t.peak_ms(), 40.0);
    }
}
