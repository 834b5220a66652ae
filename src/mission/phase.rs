//! The executive's phase (what the mission is doing) and the control
//! loop's activity within it (following, avoiding, backing off).

use super::Fault;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Phase {
    Idle,
    SelfTestScan {
        since_us: u64,
    },
    SelfTestWheels {
        until_us: u64,
        enc0: (u16, u16),
    },
    SelfTestSettle {
        until_us: u64,
    },
    Cover,
    Edge,
    ReturnSearch,
    Return,
    /// At the dock: turning in place to the heading it started with.
    Align,
    /// On the dock, charging since `since_us` from `from_pm` ‰, to go
    /// on cleaning ([`super::battery`]).
    Charging {
        since_us: u64,
        from_pm: u16,
    },
    Done,
    Failed(Fault),
}

impl Phase {
    /// The robot drives a path: covering, along the edges, or home. What
    /// a bump, a guard's hold and a relocalisation interrupt.
    pub(super) fn driving(self) -> bool {
        matches!(
            self,
            Phase::Cover | Phase::Edge | Phase::ReturnSearch | Phase::Return
        )
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Activity {
    Follow,
    Avoid,
    BackOff { until_us: u64 },
}
