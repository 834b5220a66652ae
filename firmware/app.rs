//! The robot image: the mission on the board's motors, encoders and
//! lidar, as RTIC 2 tasks (issue 11 §2).
//!
//! | task | trigger | priority | work |
//! |---|---|---|---|
//! | `control` | TIM5 compare, 100 Hz | 3 (highest) | encoders, [`Mission::control`], motors, watchdog |
//! | `lidar_dma`, `lidar_idle` | DMA half/full transfer, USART idle line | 2 | drain the DMA ring into [`Mission::feed_lidar`] |
//! | `log_tx` | USART2 transmit (feature `log-serial`) | 1 | the defmt bytes out |
//! | `idle` | background | 0 | [`Mission::plan`] when due, events and status logged |
//!
//! **Sharing.** The executive and its buffers are RTIC resources. The
//! control task locks only the executive and touches no big buffer, but a
//! planning step holds the executive while it runs (the executive is one
//! structure: its control and planning halves are not yet separate
//! resources), so a control period falls due late by up to one planning
//! step: 31.2 M instructions at worst in the whole emulated studio mission
//! (372 ms at 84 MHz), typical steps far less. The watchdog
//! ([`board::watchdog`]) bounds it: a step that holds the executive past
//! 4 s resets the chip (a whole-map relocalisation, braked, may take 3 s).
//!
//! **Watchdog.** Only `control` feeds it. When the planner has not
//! finished a turn for [`PLAN_STALL_US`], control brakes the motors and
//! goes on feeding: control alive and the motors safe, as the issue asks.
//!
//! **The mission.** Unknown mode, started at boot at the centre of a
//! 12 × 12 m map (so a home may reach 6 m from the dock each way; the map
//! does not move). Logged: every event, and every [`STATUS_US`] the
//! state, pose, coverage (planning cells cleaned, the robot's own count),
//! battery, worst task costs in cycles and the stack's high-water mark.

use super::board::{
    battery::Battery, clock, encoders, lidar_dma::LidarDma, motors::Motors, ticker, watchdog,
    wiring,
};
use super::status::{self, STATUS_US};
use core::sync::atomic::{AtomicU32, Ordering};

/// The planner has not finished a turn for this long: control brakes.
pub const PLAN_STALL_US: u64 = 1_000_000;
/// The map: 240 × 240 cells of 50 mm (12 × 12 m).
const MAP_RES_MM: u32 = 50;

/// When the planner last finished a turn, ms since boot.
static PLAN_BEAT_MS: AtomicU32 = AtomicU32::new(0);
/// Worst cycles per task (control, lidar event, plan step).
static WORST: [AtomicU32; 3] = [AtomicU32::new(0), AtomicU32::new(0), AtomicU32::new(0)];

/// Keeps the worst of a task's cycle counts.
fn note_cycles(task: usize, cycles: u32) {
    if let Some(w) = WORST.get(task) {
        w.fetch_max(cycles, Ordering::Relaxed);
    }
}

#[rtic::app(device = stm32f4xx_hal::pac, peripherals = true)]
mod app {
    use super::*;
    use cortex_m::peripheral::DWT;
    use robovac::capacity::{
        FwEvidence, FwFineGrid, FwMatcher, FwParts, FwPlanGrid, FwPlanner, FwWindow, FW_FINE_PATH,
        FW_HOME_SIDE,
    };
    use robovac::coverage::PlannerKind;
    use robovac::mission::{Mission, MotorCmd};
    use robovac::robot::hal::{ByteSource, MotorDriver, QuadratureEncoder};
    use robovac::robot::odometry::Pose;
    use robovac::Cell;
    use rtic::Mutex;
    use stm32f4xx_hal::gpio::GpioExt;

    #[shared]
    struct Shared {
        mission: &'static mut Mission,
        parts: FwParts<'static>,
        #[lock_free]
        lidar: LidarDma,
    }

    #[local]
    struct Local {
        ticker: ticker::Ticker,
        motors: Motors,
        left: encoders::LeftEncoder,
        right: encoders::RightEncoder,
        watchdog: watchdog::Watchdog,
        battery: Battery,
    }

    #[init(local = [
        mission: Mission = Mission::new(wiring::MISSION),
        planner: FwPlanner = FwPlanner::new(PlannerKind::BOha),
        search: FwWindow = FwWindow::new(),
        coarse: FwPlanGrid = FwPlanGrid::new(),
        fine: FwFineGrid = FwFineGrid::new(),
        map: FwEvidence = FwEvidence::new(),
        path: [Cell; FW_FINE_PATH] = [Cell::new(0, 0); FW_FINE_PATH],
        matcher: FwMatcher = FwMatcher::new(),
    ])]
    fn init(cx: init::Context) -> (Shared, Local) {
        super::super::stack::paint();
        let mut dp = cx.device;
        let mut core = cx.core;
        super::super::stack::guard(&mut core.MPU);
        let (sysclk, err) = clock::setup(&dp.RCC, &dp.FLASH);
        defmt::info!(
            "robovac {}: sysclk {} Hz",
            env!("CARGO_PKG_VERSION"),
            sysclk
        );
        if let Some(e) = err {
            defmt::warn!("clocks left on the internal oscillator: {}", e);
        }
        core.DCB.enable_trace();
        core.DWT.enable_cycle_counter();
        // Keep the probe's RTT link up while idle sleeps.
        dp.DBGMCU.cr().modify(|_, w| w.dbg_sleep().set_bit());
        // And stop the watchdog while a debugger halts the core.
        dp.DBGMCU
            .apb1_fz()
            .modify(|_, w| w.dbg_iwdg_stop().set_bit());
        dp.RCC.apb1enr().modify(|_, w| {
            w.tim4en().set_bit();
            w.tim5en().set_bit();
            w.usart2en().set_bit()
        });
        dp.RCC
            .apb2enr()
            .modify(|_, w| w.usart1en().set_bit().adc1en().set_bit());
        dp.RCC.ahb1enr().modify(|_, w| w.dma2en().set_bit());

        let gpioa = dp.GPIOA.split(&mut dp.RCC);
        let gpiob = dp.GPIOB.split(&mut dp.RCC);
        let gpioc = dp.GPIOC.split(&mut dp.RCC);
        let motors = Motors::new(
            (gpiob.pb6.into_alternate(), gpiob.pb7.into_alternate()),
            (
                gpioa.pa8.into_push_pull_output(),
                gpioa.pa9.into_push_pull_output(),
                gpioc.pc7.into_push_pull_output(),
                gpiob.pb5.into_push_pull_output(),
                gpiob.pb4.into_push_pull_output(),
            ),
        );
        let left = encoders::LeftEncoder::new(dp.TIM3, (gpioa.pa6, gpioa.pa7), &mut dp.RCC);
        let right = encoders::RightEncoder::new(dp.TIM2, (gpioa.pa0, gpioa.pa1), &mut dp.RCC);
        #[cfg(feature = "log-serial")]
        super::super::board::serial_log::start(gpioa.pa2.into_alternate());
        let battery = Battery::new(dp.ADC1, gpioa.pa4.into_analog());
        let lidar = LidarDma::new(gpioa.pa10.into_alternate());

        let l = cx.local;
        let mut parts = FwParts {
            planner: l.planner,
            search: l.search,
            coarse: l.coarse,
            fine: l.fine,
            map: l.map,
            path: &mut l.path[..],
            matcher: l.matcher,
        };
        let side = FW_HOME_SIDE as u32;
        if parts.map.reset(side, side, MAP_RES_MM).is_err() {
            defmt::error!("the map does not fit its buffer");
        }
        let half_mm = (side * MAP_RES_MM / 2) as i32;
        let dock = Pose {
            x_mm: half_mm,
            y_mm: half_mm,
            theta_mrad: 0,
        };
        let now = ticker::now_us();
        l.mission.begin(&mut parts, dock);
        defmt::info!(
            "mission begins at ({}, {}) mm, t {} us",
            half_mm,
            half_mm,
            now
        );
        let ticker = ticker::Ticker::start();
        let watchdog = watchdog::Watchdog::start(dp.IWDG);
        (
            Shared {
                mission: l.mission,
                parts,
                lidar,
            },
            Local {
                ticker,
                motors,
                left,
                right,
                watchdog,
                battery,
            },
        )
    }

    /// The control period: encoders in, motors out, watchdog fed.
    #[task(binds = TIM5, priority = 3, shared = [mission], local = [ticker, motors, left, right, watchdog])]
    fn control(mut cx: control::Context) {
        if !cx.local.ticker.on_interrupt() {
            return;
        }
        let t0 = DWT::cycle_count();
        let now = ticker::now_us();
        let enc = (cx.local.left.count(), cx.local.right.count());
        let cmd = cx.shared.mission.lock(|m| m.control(now, enc));
        let beat_ms = u64::from(PLAN_BEAT_MS.load(Ordering::Relaxed));
        let planner_alive = (now / 1000).saturating_sub(beat_ms) * 1000 < PLAN_STALL_US;
        match cmd {
            MotorCmd::Duty(l, r) if planner_alive => cx.local.motors.set_duty(l, r),
            _ => cx.local.motors.brake(),
        }
        cx.local.watchdog.feed();
        note_cycles(0, DWT::cycle_count().wrapping_sub(t0));
    }

    /// Half or all of the DMA ring filled.
    #[task(binds = DMA2_STREAM2, priority = 2, shared = [mission, parts, lidar])]
    fn lidar_dma(cx: lidar_dma::Context) {
        cx.shared.lidar.on_dma();
        feed(cx.shared.lidar, cx.shared.mission, cx.shared.parts);
    }

    /// The lidar's line went idle (a frame ended), or a receive error.
    #[task(binds = USART1, priority = 2, shared = [mission, parts, lidar])]
    fn lidar_idle(cx: lidar_idle::Context) {
        cx.shared.lidar.on_usart();
        feed(cx.shared.lidar, cx.shared.mission, cx.shared.parts);
    }

    /// The defmt serial port's transmitter (enabled with `log-serial`).
    #[task(binds = USART2, priority = 1)]
    fn log_tx(_: log_tx::Context) {
        #[cfg(feature = "log-serial")]
        super::super::board::serial_log::on_interrupt();
    }

    /// Planning, events and status, in the background.
    #[idle(shared = [mission, parts], local = [battery])]
    fn idle(mut cx: idle::Context) -> ! {
        let mut next_status = STATUS_US;
        loop {
            let now = ticker::now_us();
            let t0 = DWT::cycle_count();
            let planned = (&mut cx.shared.mission, &mut cx.shared.parts).lock(|m, p| {
                let due = m.plan_due(now);
                m.plan(p, now);
                due
            });
            if planned {
                note_cycles(2, DWT::cycle_count().wrapping_sub(t0));
            }
            PLAN_BEAT_MS.store((now / 1000) as u32, Ordering::Relaxed);
            while let Some(e) = cx.shared.mission.lock(|m| m.pop_event()) {
                status::event(&e);
            }
            if now >= next_status {
                next_status = now + STATUS_US;
                (&mut cx.shared.mission, &mut cx.shared.parts)
                    .lock(|m, p| status::status(now, m, p.coarse));
                health(&mut cx.shared.mission, cx.local.battery);
            }
            if !planned {
                cortex_m::asm::wfi();
            }
        }
    }

    /// Drains the lidar's ring into the executive.
    fn feed(
        lidar: &mut LidarDma,
        mut mission: impl Mutex<T = &'static mut Mission>,
        mut parts: impl Mutex<T = FwParts<'static>>,
    ) {
        let t0 = DWT::cycle_count();
        let now = ticker::now_us();
        let mut buf = [0u8; 256];
        loop {
            let n = lidar.read(&mut buf);
            if n == 0 {
                break;
            }
            let bytes = buf.get(..n).unwrap_or(&[]);
            mission.lock(|m| parts.lock(|p| m.feed_lidar(p, bytes, now)));
        }
        note_cycles(1, DWT::cycle_count().wrapping_sub(t0));
    }

    /// The robot's health: battery, worst task costs, stack, lidar.
    fn health(mission: &mut impl Mutex<T = &'static mut Mission>, battery: &mut Battery) {
        let (counters, parser) = mission.lock(|m| (m.counters(), m.parser_stats()));
        defmt::info!("battery {} mV", battery.read_mv().unwrap_or(0));
        defmt::info!(
            "worst cycles: control {}, lidar event {}, plan step {} (budget {} per 10 ms); stack {} of {} bytes; scans {}, plan steps {}",
            WORST[0].load(Ordering::Relaxed),
            WORST[1].load(Ordering::Relaxed),
            WORST[2].load(Ordering::Relaxed),
            clock::SYSCLK_HZ / 100,
            super::super::stack::used(),
            super::super::stack::size(),
            counters.scans,
            counters.plan_steps
        );
        defmt::info!(
            "lidar: {} frames, {} bad checksums, {} rejected, {} bytes skipped; {} UART errors; {} log frames dropped",
            parser.frames,
            parser.crc_failures,
            parser.rejected,
            parser.bytes_skipped,
            super::super::board::lidar_dma::errors(),
            super::super::log::dropped()
        );
        #[cfg(feature = "log-serial")]
        defmt::info!(
            "serial log: {} bytes dropped (ring full)",
            super::super::board::serial_log::dropped()
        );
    }
}
