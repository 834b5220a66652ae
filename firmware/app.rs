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
//! **Sharing without blocking.** The executive and its buffers sit in one
//! try-lock ([`EXEC`], a `spin` mutex only ever tried, never waited on),
//! not in an RTIC resource: RTIC's locks raise the holder to the
//! resource's ceiling, so a planning step (up to 31.2 M instructions,
//! 372 ms at 84 MHz, in the whole emulated studio mission) would hold the
//! control interrupt off for its whole length, and the robot would drive
//! on unguarded. Instead, whoever finds the executive held does without:
//!
//! - control runs the [`Reflex`]: it keeps the last command for
//!   [`Reflex::HOLD_US`] (60 ms), then brakes, and feeds the watchdog
//!   unless the executive has been held for [`Reflex::HUNG_US`] (6 s);
//! - a lidar event leaves its bytes in the DMA ring;
//! - both are owed: whoever releases the executive pends the owed control
//!   period and lidar event, so they run the moment it comes free.
//!
//! A control period is thus late by at most the step that holds the
//! executive, and never more than the hold unbraked. Measured in the loop
//! (the studio, first 120 s): a lidar event takes about 0.1 M
//! instructions, and 3.7 M on average at the end of a revolution (the
//! scan matched and ray-cast; 22.8 M for the relocalisation at the
//! self-test, braked); plan steps rarely pass 25 ms since the planning
//! cells are derived again only where the map changed. The cost: on the
//! robot, a step longer than 60 ms brakes the robot for its remainder
//! (the loop's figures count them: `pil_compare.py`).
//!
//! **Watchdog.** Only `control` feeds it. When the planner has not
//! finished a turn for [`PLAN_STALL_US`], control brakes the motors and
//! goes on feeding: control alive and the motors safe, as the issue asks.
//! An executive held past [`Reflex::HUNG_US`] stops the feeding: the chip
//! resets within the watchdog's 0.5 s more.
//!
//! **The mission.** The robot stands braked from boot until the button
//! ([`wiring::ButtonPin`], debounced by control) is pressed: a freshly
//! flashed robot on a bench does not drive off. The first press begins the
//! mission, a later one sends the robot home
//! ([`Mission::request_home`]). Unknown mode, at the centre of a
//! 12 × 12 m map (so a home may reach 6 m from the dock each way; the map
//! does not move). **The map kept between runs:** once a mission is done
//! (docked), the map and the dock's pose on it are saved to flash sector 7
//! ([`FlashStore`]; the erase stalls the CPU up to 2 s, so control first
//! stretches the watchdog to [`ERASE_WATCHDOG_MS`]); at the next boot the
//! mission starts from that map at its dock and relocalises there
//! (`prior_saved`). A damaged map is logged and a fresh one begun. Logged: every event, and every [`STATUS_US`] the
//! state, pose, coverage (planning cells cleaned, the robot's own count),
//! battery, worst task costs in cycles and the stack's high-water mark.

use super::board::{
    battery::Battery, bumper::Switches, clock, encoders, flash_store::FlashStore,
    lidar_dma::LidarDma, motors::Motors, ticker, watchdog, wiring,
};
use super::status::{self, STATUS_US};
use core::sync::atomic::{AtomicBool, AtomicU32, AtomicU8, Ordering};
use robovac::capacity::FwParts;
use robovac::mission::{Mission, Reflex};

/// The planner has not finished a turn for this long: control brakes.
pub const PLAN_STALL_US: u64 = 1_000_000;
/// The map: 240 × 240 cells of 50 mm (12 × 12 m).
const MAP_RES_MM: u32 = 50;

/// When the planner last finished a turn, ms since boot.
static PLAN_BEAT_MS: AtomicU32 = AtomicU32::new(0);
/// Worst cycles per task (control, lidar event, plan step).
static WORST: [AtomicU32; 3] = [AtomicU32::new(0), AtomicU32::new(0), AtomicU32::new(0)];

/// The executive at work on its buffers.
pub struct Exec {
    mission: &'static mut Mission,
    parts: FwParts<'static>,
}

/// The executive, shared by control, the lidar events and idle: only ever
/// tried, never waited on (see the module docs).
static EXEC: spin::Mutex<Option<Exec>> = spin::Mutex::new(None);
/// A control period found the executive held: run it when it comes free.
static CONTROL_OWED: AtomicBool = AtomicBool::new(false);
/// A lidar event found the executive held: its bytes wait in the DMA ring.
static LIDAR_OWED: AtomicBool = AtomicBool::new(false);
/// The button was pressed (control debounces it; idle acts on it).
static BUTTON: AtomicBool = AtomicBool::new(false);
/// Saving the map at the end ([`save_step`]): idle asks, control
/// stretches the watchdog over the flash erase's stall, idle saves,
/// control sets the watchdog back.
static SAVE: AtomicU8 = AtomicU8::new(save::NONE);

/// The steps of [`SAVE`].
mod save {
    pub const NONE: u8 = 0;
    pub const ASKED: u8 = 1;
    pub const STRETCHED: u8 = 2;
    pub const SAVED: u8 = 3;
    pub const OVER: u8 = 4;
}
/// The watchdog's timeout while the store's sector erases (up to 2 s).
const ERASE_WATCHDOG_MS: u32 = 4_000;

/// Runs `f` on the executive, unless another task holds it (`None`);
/// then runs the control period and lidar event owed meanwhile.
fn with_exec<R>(f: impl FnOnce(&mut Exec) -> R) -> Option<R> {
    let r = {
        let mut guard = EXEC.try_lock()?;
        guard.as_mut().map(f)
    };
    if CONTROL_OWED.load(Ordering::Relaxed) {
        rtic::pend(stm32f4xx_hal::pac::Interrupt::TIM5);
    }
    if LIDAR_OWED.swap(false, Ordering::Relaxed) {
        rtic::pend(stm32f4xx_hal::pac::Interrupt::DMA2_STREAM2);
    }
    r
}

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
        FwEvidence, FwFineGrid, FwMatcher, FwPlanGrid, FwPlanner, FwWindow, FW_FINE_PATH,
        FW_HOME_SIDE, FW_PLAN_CELLS,
    };
    use robovac::coverage::PlannerKind;
    use robovac::mission::MotorCmd;
    use robovac::robot::debounce::Debounce;
    use robovac::robot::hal::{BumperSwitches, ByteSource, MotorDriver, QuadratureEncoder};
    use robovac::robot::odometry::Pose;
    use robovac::Cell;
    use stm32f4xx_hal::gpio::GpioExt;

    #[shared]
    struct Shared {
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
        store: FlashStore,
        saved_dock: Option<Pose>,
        button: wiring::ButtonPin,
        bumper: Switches,
    }

    #[init(local = [
        mission: Mission = Mission::new(wiring::MISSION),
        planner: FwPlanner = FwPlanner::new(PlannerKind::BOha),
        search: FwWindow = FwWindow::new(),
        coarse: FwPlanGrid = FwPlanGrid::new(),
        fine: FwFineGrid = FwFineGrid::new(),
        // The CCM's at 16 x 16 m (`ccm`).
        #[cfg_attr(feature = "home16", link_section = ".ccmram.map")]
        map: FwEvidence = FwEvidence::new(),
        path: [Cell; FW_FINE_PATH] = [Cell::new(0, 0); FW_FINE_PATH],
        matcher: FwMatcher = FwMatcher::new(),
        rooms: [u8; FW_PLAN_CELLS] = [0; FW_PLAN_CELLS],
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
        let button = gpioc.pc13.into_input();
        let bumper = Switches::new(
            gpioc.pc0.into_pull_up_input(),
            gpioc.pc1.into_pull_up_input(),
        );
        let lidar = LidarDma::new(gpioa.pa10.into_alternate());

        let l = cx.local;
        let parts = FwParts {
            planner: l.planner,
            search: l.search,
            coarse: l.coarse,
            fine: l.fine,
            map: l.map,
            path: &mut l.path[..],
            matcher: l.matcher,
            rooms: &mut l.rooms[..],
        };
        let mut store = FlashStore::new(dp.FLASH);
        let saved_dock = load_map(&mut store, l.mission, parts.map);
        defmt::info!("press the button (B1) to start; press it again to send the robot home");
        if let Some(mut exec) = EXEC.try_lock() {
            *exec = Some(Exec {
                mission: l.mission,
                parts,
            });
        }
        let ticker = ticker::Ticker::start();
        let watchdog = watchdog::Watchdog::start(dp.IWDG);
        (
            Shared { lidar },
            Local {
                ticker,
                motors,
                left,
                right,
                watchdog,
                battery,
                store,
                saved_dock,
                button,
                bumper,
            },
        )
    }

    /// The control period: encoders in, motors out, watchdog fed; the
    /// reflex when the executive is held (also run when pended as owed).
    #[task(binds = TIM5, priority = 3, local = [ticker, motors, left, right, watchdog, button, bumper, reflex: Reflex = Reflex::new(), debounce: Debounce = Debounce::new()])]
    fn control(cx: control::Context) {
        let due = cx.local.ticker.on_interrupt();
        let owed = CONTROL_OWED.swap(false, Ordering::Relaxed);
        if !due && !owed {
            return;
        }
        let t0 = DWT::cycle_count();
        let now = ticker::now_us();
        let closed = cx.local.button.is_low() == wiring::BUTTON_ACTIVE_LOW;
        if due && cx.local.debounce.poll(closed) {
            BUTTON.store(true, Ordering::Relaxed);
        }
        let enc = (cx.local.left.count(), cx.local.right.count());
        let bumper = cx.local.bumper.read_bumper();
        // Inside the try-lock: control preempted nothing that holds it.
        let ran = EXEC.try_lock().and_then(|mut g| {
            g.as_mut().map(|e| {
                e.mission.set_bumper(bumper);
                e.mission.control(now, enc)
            })
        });
        let (cmd, feed) = match ran {
            Some(cmd) => {
                cx.local.reflex.ran(now, cmd);
                (cmd, true)
            }
            None => {
                CONTROL_OWED.store(true, Ordering::Relaxed);
                let out = cx.local.reflex.busy(now);
                (out.cmd, out.feed)
            }
        };
        let beat_ms = u64::from(PLAN_BEAT_MS.load(Ordering::Relaxed));
        let planner_alive = (now / 1000).saturating_sub(beat_ms) * 1000 < PLAN_STALL_US;
        match cmd {
            MotorCmd::Duty(l, r) if planner_alive => cx.local.motors.set_duty(l, r),
            _ => cx.local.motors.brake(),
        }
        match SAVE.load(Ordering::Relaxed) {
            save::ASKED => {
                cx.local.watchdog.set_timeout_ms(ERASE_WATCHDOG_MS);
                SAVE.store(save::STRETCHED, Ordering::Relaxed);
            }
            save::SAVED => {
                cx.local.watchdog.set_timeout_ms(watchdog::TIMEOUT_MS);
                SAVE.store(save::OVER, Ordering::Relaxed);
            }
            _ => {}
        }
        if feed {
            cx.local.watchdog.feed();
        }
        note_cycles(0, DWT::cycle_count().wrapping_sub(t0));
    }

    /// Half or all of the DMA ring filled.
    /// (Also pended when a held executive comes free.)
    #[task(binds = DMA2_STREAM2, priority = 2, shared = [lidar])]
    fn lidar_dma(cx: lidar_dma::Context) {
        cx.shared.lidar.on_dma();
        feed(cx.shared.lidar);
    }

    /// The lidar's line went idle (a frame ended), or a receive error.
    #[task(binds = USART1, priority = 2, shared = [lidar])]
    fn lidar_idle(cx: lidar_idle::Context) {
        cx.shared.lidar.on_usart();
        feed(cx.shared.lidar);
    }

    /// The defmt serial port's transmitter (enabled with `log-serial`).
    #[task(binds = USART2, priority = 1)]
    fn log_tx(_: log_tx::Context) {
        #[cfg(feature = "log-serial")]
        super::super::board::serial_log::on_interrupt();
    }

    /// Planning, events and status, in the background.
    /// Idle holds the executive only between its own steps' ends, so its
    /// try-lock never finds it held (every task that takes it preempts
    /// idle and lets go before idle resumes).
    #[idle(local = [battery, store, saved_dock])]
    fn idle(cx: idle::Context) -> ! {
        let mut next_status = STATUS_US;
        let mut begun = false;
        loop {
            let now = ticker::now_us();
            if BUTTON.swap(false, Ordering::Relaxed) {
                begun |= on_button(begun, now, *cx.local.saved_dock);
            }
            if begun {
                save_step(cx.local.store);
            }
            let t0 = DWT::cycle_count();
            let planned = with_exec(|e| {
                let due = e.mission.plan_due(now);
                e.mission.plan(&mut e.parts, now);
                due
            })
            .unwrap_or(false);
            if planned {
                note_cycles(2, DWT::cycle_count().wrapping_sub(t0));
            }
            PLAN_BEAT_MS.store((now / 1000) as u32, Ordering::Relaxed);
            while let Some(e) = with_exec(|e| e.mission.pop_event()).flatten() {
                status::event(&e);
            }
            if now >= next_status {
                next_status = now + STATUS_US;
                with_exec(|e| status::status(now, e.mission, e.parts.coarse));
                health(cx.local.battery);
            }
            if !planned {
                cortex_m::asm::wfi();
            }
        }
    }

    /// The button: the first press begins the mission (the robot stands
    /// braked until then), a later one sends the robot home. True when
    /// the mission has begun.
    fn on_button(begun: bool, now: u64, saved_dock: Option<Pose>) -> bool {
        if begun {
            defmt::info!("button: going home");
            with_exec(|e| e.mission.request_home());
            return true;
        }
        let half_mm = (FW_HOME_SIDE as u32 * MAP_RES_MM / 2) as i32;
        let dock = saved_dock.unwrap_or(Pose {
            x_mm: half_mm,
            y_mm: half_mm,
            theta_mrad: 0,
        });
        let ok = with_exec(|e| e.mission.begin(&mut e.parts, dock)).is_some();
        defmt::info!(
            "button: mission begins at ({}, {}) mm, t {} us",
            dock.x_mm,
            dock.y_mm,
            now
        );
        ok
    }

    /// At boot: the map a finished run saved, when the store holds one
    /// (the mission then starts from it, at its dock, relocalising there);
    /// else an empty 12 × 12 m map with the dock at its centre.
    fn load_map(
        store: &mut FlashStore,
        mission: &mut Mission,
        map: &mut FwEvidence,
    ) -> Option<Pose> {
        match robovac::robot::map_image::load(store, map) {
            Ok(dock) => {
                let mut cfg = wiring::MISSION;
                cfg.prior_saved = true;
                mission.configure(cfg);
                defmt::info!(
                    "saved map loaded: {}x{} cells, dock at ({}, {}) mm",
                    map.width(),
                    map.height(),
                    dock.x_mm,
                    dock.y_mm
                );
                return Some(dock);
            }
            Err(robovac::robot::map_image::MapImageError::NoMap) => {}
            Err(e) => status::map_store("saved map refused", &e),
        }
        let side = FW_HOME_SIDE as u32;
        if map.reset(side, side, MAP_RES_MM).is_err() {
            defmt::error!("the map does not fit its buffer");
        }
        None
    }

    /// Once the mission is done (docked, motors braked): save the map for
    /// the next run, the watchdog stretched by control over the erase.
    fn save_step(store: &mut FlashStore) {
        match SAVE.load(Ordering::Relaxed) {
            save::NONE => {
                let done = with_exec(|e| e.mission.state() == robovac::mission::State::Done);
                if done == Some(true) {
                    SAVE.store(save::ASKED, Ordering::Relaxed);
                }
            }
            save::STRETCHED => {
                let r = with_exec(|e| {
                    robovac::robot::map_image::save(e.parts.map, e.mission.dock(), store)
                });
                match r {
                    Some(Ok(n)) => defmt::info!("map saved for the next run: {} bytes", n),
                    Some(Err(e)) => status::map_store("map not saved", &e),
                    None => return,
                }
                SAVE.store(save::SAVED, Ordering::Relaxed);
            }
            _ => {}
        }
    }

    /// Drains the lidar's ring into the executive; when another task
    /// holds it, the bytes wait in the ring and the event is owed.
    fn feed(lidar: &mut LidarDma) {
        let t0 = DWT::cycle_count();
        let now = ticker::now_us();
        let fed = with_exec(|e| {
            let mut buf = [0u8; 256];
            loop {
                let n = lidar.read(&mut buf);
                if n == 0 {
                    break;
                }
                let bytes = buf.get(..n).unwrap_or(&[]);
                e.mission.feed_lidar(&mut e.parts, bytes, now);
            }
        });
        if fed.is_none() {
            LIDAR_OWED.store(true, Ordering::Relaxed);
        }
        note_cycles(1, DWT::cycle_count().wrapping_sub(t0));
    }

    /// The robot's health: battery, worst task costs, stack, lidar.
    fn health(battery: &mut Battery) {
        let Some((counters, parser)) =
            with_exec(|e| (e.mission.counters(), e.mission.parser_stats()))
        else {
            return;
        };
        let mv = battery.read_mv();
        defmt::info!("battery {} mV", mv.unwrap_or(0));
        // The charge decides when to go home to recharge. A pin reading
        // below 2.5 V a cell has no pack behind it (the divider is not
        // wired, or no ADC: the emulator): the time budget then applies.
        if let Some(mv) = mv.filter(|&mv| mv >= wiring::BATTERY_CELLS * 2_500) {
            let pm = robovac::robot::battery::charge_from_mv(mv, wiring::BATTERY_CELLS);
            with_exec(|e| e.mission.set_charge(pm));
        }
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
