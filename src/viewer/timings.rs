//! Frame timings for the UI: CPU frame time and GPU milliseconds per pass, with a short
//! history for the graph.

use std::collections::VecDeque;

/// Frames kept for the graph.
pub const HISTORY: usize = 240;

/// One frame's times in milliseconds.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameTimes {
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

    /// Mean CPU frame time and mean GPU time of each pass over the history.
    pub fn mean(&self) -> FrameTimes {
        let n = self.history.len().max(1) as f64;
        let passes = self.history.iter().map(|t| t.gpu_ms.len()).max().unwrap_or(0);
        let mut gpu_ms = vec![0.0; passes];
        for t in &self.history {
            for (sum, ms) in gpu_ms.iter_mut().zip(&t.gpu_ms) {
                *sum += ms / n;
            }
        }
        FrameTimes {
            cpu_ms: self.history.iter().map(|t| t.cpu_ms).sum::<f64>() / n,
            gpu_ms,
        }
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

    fn times(cpu: f64, gpu: &[f64]) -> FrameTimes {
        FrameTimes {
            cpu_ms: cpu,
            gpu_ms: gpu.to_vec(),
        }
    }

    #[test]
    fn history_is_bounded_and_keeps_the_newest() {
        let mut t = Timings::new(vec!["a"]);
        for i in 0..HISTORY + 10 {
            t.push(times(i as f64, &[1.0]));
        }
        assert_eq!(t.history().len(), HISTORY);
        assert_eq!(t.history().next().map(|f| f.cpu_ms), Some(10.0));
        assert_eq!(t.history().last().map(|f| f.cpu_ms), Some((HISTORY + 9) as f64));
    }

    #[test]
    fn mean_and_peak() {
        let mut t = Timings::new(vec!["forward", "tonemap"]);
        assert_eq!(t.mean(), FrameTimes::default());
        assert_eq!(t.peak_ms(), 0.0);
        t.push(times(10.0, &[2.0, 1.0]));
        t.push(times(20.0, &[4.0, 3.0]));
        assert_eq!(t.mean(), times(15.0, &[3.0, 2.0]));
        assert_eq!(t.peak_ms(), 20.0);
        t.push(times(1.0, &[30.0, 1.0]));
        assert_eq!(t.peak_ms(), 31.0);
    }
}
