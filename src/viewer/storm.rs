//! The resize storm (`argil view --resize-storm`, for tests): a fixed schedule of window
//! resizes, a minimise and a restore while frames are rendered, to exercise swapchain
//! recreation.

/// Something the storm does to the window.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StormStep {
    Resize(u32, u32),
    Minimise,
    Restore,
}

/// Ticks (redraw requests) between two steps: a few frames render at each size.
pub const TICKS_PER_STEP: u64 = 3;

/// Sizes from tiny to large, tall and wide, then back to the start.
const STEPS: [StormStep; 11] = [
    StormStep::Resize(640, 360),
    StormStep::Resize(1, 1),
    StormStep::Resize(1024, 640),
    StormStep::Resize(333, 777),
    StormStep::Minimise,
    StormStep::Restore,
    StormStep::Resize(900, 64),
    StormStep::Resize(64, 64),
    StormStep::Minimise,
    StormStep::Restore,
    StormStep::Resize(800, 450),
];

/// The step to take at `tick`, if any.
pub fn step(tick: u64) -> Option<StormStep> {
    if tick == 0 || tick % TICKS_PER_STEP != 0 {
        return None;
    }
    STEPS.get((tick / TICKS_PER_STEP - 1) as usize).copied()
}

/// Ticks the whole storm takes.
pub const DURATION: u64 = (STEPS.len() as u64 + 1) * TICKS_PER_STEP;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_step_happens_once_in_order_then_nothing() {
        let steps: Vec<StormStep> = (0..DURATION * 2).filter_map(step).collect();
        assert_eq!(steps, STEPS.to_vec());
        let resizes = steps.iter().filter(|s| matches!(s, StormStep::Resize(..))).count();
        let minimised = steps.iter().filter(|s| **s == StormStep::Minimise).count();
        assert_eq!((resizes, minimised), (7, 2));
        assert_eq!(steps.iter().filter(|s| **s == StormStep::Restore).count(), minimised);
    }
}
