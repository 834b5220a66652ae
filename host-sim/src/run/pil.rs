//! Processor-in-the-loop (issue 11 §4): the firmware image built with the
//! sim-link board runs in QEMU's `netduinoplus2`; this process is its
//! robot. QEMU's USART1 (the LD06 bytes), USART2 (the sim link) and
//! USART6 (the defmt log) are Unix sockets this process listens on.
//!
//! Lock-step: every control period the physics advances, the period's
//! lidar bytes go out on USART1 and a tick on USART2; the firmware answers
//! with its motor command (and any events) before the next period, so the
//! run does not depend on how fast either side is.

use std::io::{BufReader, Read, Write};
use std::os::unix::net::{UnixListener, UnixStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use robovac::link::msg::{pack_row, Down, Hello, PackedRow, Report, StepMsg, Tick, Up};
use robovac::link::{encode, FrameReader, MAX_FRAME};
use robovac::localize::LocStats;
use robovac::mission::{Counters, Event, MissionConfig, MotorCmd, State};
use robovac::robot::lidar_map::EvidenceMap;
use robovac::robot::odometry::Pose;

use super::executive::{Executive, Sensors};

/// Where the firmware image is and where its log goes.
#[derive(Clone, Debug)]
pub struct PilOptions {
    /// The image built with the sim-link board (`--features pil`).
    pub elf: PathBuf,
    /// The raw defmt log, if wanted.
    pub log: Option<PathBuf>,
}

/// Instructions per 10 ms control period at 84 MHz (the F411's clock).
pub const BUDGET_84MHZ_10MS: u64 = 840_000;

/// What the firmware measured on itself, for the mission's report.
#[derive(Clone, Debug, serde::Serialize)]
pub struct FirmwareFigures {
    /// Worst control tick, instructions.
    pub worst_control_insn: u64,
    /// Worst lidar event (a period's bytes), instructions.
    pub worst_lidar_insn: u64,
    /// Worst plan step, instructions.
    pub worst_plan_insn: u64,
    /// The control tick's worst case as a share of its 10 ms period at
    /// 84 MHz (the bound: 20 %).
    pub control_share_of_period: f64,
    /// Plan steps and lidar events that held the executive past the
    /// control reflex's hold (60 ms at 84 MHz) while the robot drove: the
    /// robot image brakes for their remainder.
    pub plan_steps_over_hold: u32,
    /// Lidar events likewise.
    pub lidar_events_over_hold: u32,
    /// The time the robot image would stand braked by the reflex, s.
    pub reflex_braked_s: f64,
    /// Every task's instructions over the mission, and their share of
    /// the F411's 84 MHz over the mission's time (the processor's load,
    /// counting one instruction a cycle).
    pub total_insn: u64,
    /// Stack used at most, bytes.
    pub stack_used_bytes: u32,
    /// Stack available, bytes.
    pub stack_size_bytes: u32,
    /// Link frames the firmware decoded, and dropped (CRC, framing, too
    /// long, not a message).
    pub link_frames: u32,
    /// Link frames dropped.
    pub link_dropped: u32,
    /// USART receive errors and bytes lost to a full queue.
    pub rx_errors: u32,
    /// Bytes lost to a full receive queue.
    pub rx_dropped: u32,
    /// The lidar parser's counters: frames, CRC errors.
    pub lidar_frames: u32,
    /// Lidar frames with a bad CRC.
    pub lidar_crc_errors: u32,
}

impl From<Report> for FirmwareFigures {
    fn from(r: Report) -> Self {
        let l = r.link;
        Self {
            worst_control_insn: r.worst.control,
            worst_lidar_insn: r.worst.lidar,
            worst_plan_insn: r.worst.plan,
            control_share_of_period: r.worst.control as f64 / BUDGET_84MHZ_10MS as f64,
            plan_steps_over_hold: r.worst.plan_over_hold,
            lidar_events_over_hold: r.worst.lidar_over_hold,
            reflex_braked_s: r.worst.braked_insn as f64 / (BUDGET_84MHZ_10MS as f64 * 100.0),
            total_insn: r.worst.total_insn,
            stack_used_bytes: r.stack_used,
            stack_size_bytes: r.stack_size,
            link_frames: l.frames,
            link_dropped: l.crc + l.framing + l.too_long + l.decode,
            rx_errors: r.rx_errors,
            rx_dropped: r.rx_dropped,
            lidar_frames: r.parser.frames,
            lidar_crc_errors: r.parser.crc_failures,
        }
    }
}

/// How long the firmware may take to answer (wall time).
const ANSWER_TIMEOUT: Duration = Duration::from_secs(60);

/// The firmware in the emulator, as the mission loop's executive.
pub struct Pil {
    qemu: Child,
    lidar: UnixStream,
    link: UnixStream,
    link_in: BufReader<UnixStream>,
    reader: FrameReader<MAX_FRAME>,
    /// The mission's configuration and prior map, sent at `begin`.
    cfg: MissionConfig,
    rows: Vec<(u16, PackedRow)>,
    map_dims: (u16, u16, u16),
    last: StepMsg,
    events: std::collections::VecDeque<Event>,
    /// The firmware's end-of-mission report.
    pub report: Option<Report>,
    /// The firmware's map frame against the world's.
    pub frame: super::executive::Frame,
    _dir: TempDir,
}

/// A directory removed when dropped.
struct TempDir(PathBuf);
impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

impl Pil {
    /// [`Self::start`] with the prior of `world` (known mode) filled into
    /// `map`, an empty evidence map of the image's capacity.
    pub(crate) fn start_on<const B: usize>(
        pil: &PilOptions,
        cfg: MissionConfig,
        mut map: Box<EvidenceMap<B>>,
        world: &crate::sim::world::World,
        known: bool,
    ) -> Result<Self, String> {
        crate::sim::scan::fill_prior(&mut map, world, super::mission::EVIDENCE_MM, known)?;
        Self::start(&pil.elf, pil.log.as_deref(), cfg, &map)
    }

    /// Boots `elf` in QEMU and waits for its Ready. The defmt log goes to
    /// `log` (raw defmt frames: `defmt-print -e ELF < LOG`).
    pub fn start<const B: usize>(
        elf: &Path,
        log: Option<&Path>,
        cfg: MissionConfig,
        map: &EvidenceMap<B>,
    ) -> Result<Self, String> {
        let dir = std::env::temp_dir().join(format!("robovac-pil-{}", std::process::id()));
        std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        let dir = TempDir(dir);
        let sock = |n: &str| dir.0.join(n);
        let bind = |p: &Path| UnixListener::bind(p).map_err(|e| format!("{}: {e}", p.display()));
        let (l_lidar, l_link, l_log) = (
            bind(&sock("lidar"))?,
            bind(&sock("link"))?,
            bind(&sock("log"))?,
        );
        let qemu = spawn_qemu(elf, &sock("lidar"), &sock("link"), &sock("log"))?;
        let lidar = accept(&l_lidar)?;
        let link = accept(&l_link)?;
        let log_in = accept(&l_log)?;
        drain_log(log_in, log.map(Path::to_path_buf));
        link.set_read_timeout(Some(ANSWER_TIMEOUT))
            .map_err(|e| e.to_string())?;
        let link_in = BufReader::new(link.try_clone().map_err(|e| e.to_string())?);
        let mut pil = Self {
            qemu,
            lidar,
            link,
            link_in,
            reader: FrameReader::new(),
            cfg,
            rows: prior_rows(map),
            map_dims: (map.width() as u16, map.height() as u16, map.res_mm() as u16),
            last: StepMsg {
                cmd: MotorCmd::Brake,
                state: State::SelfTest,
                pose: Pose::default(),
                lost: false,
                avoidance_events: 0,
                finished: false,
            },
            events: Default::default(),
            report: None,
            frame: Default::default(),
            _dir: dir,
        };
        match pil.recv()? {
            Up::Ready(_) => Ok(pil),
            other => Err(format!("the firmware did not boot: {other:?}")),
        }
    }

    fn send(&mut self, msg: &Down) -> Result<(), String> {
        let mut buf = [0u8; MAX_FRAME];
        let n = encode(msg, &mut buf).map_err(|e| e.as_str().to_string())?;
        self.link
            .write_all(buf.get(..n).unwrap_or(&[]))
            .map_err(|e| format!("sim link: {e}"))
    }

    /// The next message from the firmware.
    fn recv(&mut self) -> Result<Up, String> {
        let mut b = [0u8; 1];
        loop {
            self.link_in
                .read_exact(&mut b)
                .map_err(|e| format!("sim link: the firmware did not answer ({e})"))?;
            if let Some(Ok(m)) = self.reader.push::<Up>(b[0]) {
                return Ok(m);
            }
        }
    }

    /// Messages until a step (events are queued on the way).
    fn recv_step(&mut self) -> Result<StepMsg, String> {
        loop {
            match self.recv()? {
                Up::Step(s) => return Ok(s),
                Up::Event(e) => self.events.push_back(e),
                other => return Err(format!("sim link: unexpected {other:?}")),
            }
        }
    }
}

impl Drop for Pil {
    fn drop(&mut self) {
        let _ = self.qemu.kill();
        let _ = self.qemu.wait();
    }
}

/// The prior map's rows, packed (unknown mode: all unknown, none sent).
fn prior_rows<const B: usize>(map: &EvidenceMap<B>) -> Vec<(u16, PackedRow)> {
    let (w, h) = (map.width() as i32, map.height() as i32);
    let mut rows = Vec::new();
    for y in 0..h {
        let states: Vec<_> = (0..w).map(|x| map.state(x, y)).collect();
        if states
            .iter()
            .all(|s| *s == robovac::robot::lidar_map::CellState::Unknown)
        {
            continue;
        }
        if let Some(packed) = pack_row(states) {
            rows.push((y as u16, packed));
        }
    }
    rows
}

fn spawn_qemu(elf: &Path, lidar: &Path, link: &Path, log: &Path) -> Result<Child, String> {
    let serial = |p: &Path| format!("unix:{}", p.display());
    Command::new(std::env::var("QEMU").unwrap_or_else(|_| "qemu-system-arm".into()))
        .args([
            "-machine",
            "netduinoplus2",
            "-cpu",
            "cortex-m4",
            "-icount",
            "shift=0,sleep=off",
        ])
        .args(["-nographic", "-monitor", "none"])
        .args(["-serial", &serial(lidar), "-serial", &serial(link)])
        .args(["-serial", "null", "-serial", "null", "-serial", "null"])
        .args(["-serial", &serial(log)])
        .arg("-kernel")
        .arg(elf)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::inherit())
        .spawn()
        .map_err(|e| format!("qemu-system-arm: {e}"))
}

/// Accepts QEMU's connection (within 30 s).
fn accept(l: &UnixListener) -> Result<UnixStream, String> {
    l.set_nonblocking(true).map_err(|e| e.to_string())?;
    let t0 = Instant::now();
    loop {
        match l.accept() {
            Ok((s, _)) => {
                s.set_nonblocking(false).map_err(|e| e.to_string())?;
                return Ok(s);
            }
            Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => {
                if t0.elapsed() > Duration::from_secs(30) {
                    return Err("QEMU did not connect its serial ports".into());
                }
                std::thread::sleep(Duration::from_millis(10));
            }
            Err(e) => return Err(e.to_string()),
        }
    }
}

/// Copies the defmt log to a file (or discards it) in the background.
fn drain_log(mut from: UnixStream, to: Option<PathBuf>) {
    std::thread::spawn(move || {
        let mut out = to.and_then(|p| std::fs::File::create(p).ok());
        let mut buf = [0u8; 4096];
        while let Ok(n) = from.read(&mut buf) {
            if n == 0 {
                break;
            }
            if let Some(f) = out.as_mut() {
                let _ = f.write_all(buf.get(..n).unwrap_or(&[]));
            }
        }
    });
}

impl Executive for Pil {
    fn begin(&mut self, dock: Pose) -> Result<(), String> {
        let (map_w, map_h, res_mm) = self.map_dims;
        self.send(&Down::Hello(Hello {
            cfg: self.cfg,
            dock: self.frame.to_map(dock),
            map_w,
            map_h,
            res_mm,
        }))?;
        for (row, cells) in std::mem::take(&mut self.rows) {
            self.send(&Down::MapRow { row, cells })?;
        }
        self.send(&Down::Start)
    }

    fn period(&mut self, s: &Sensors<'_>) -> Result<MotorCmd, String> {
        self.lidar
            .write_all(s.lidar)
            .map_err(|e| format!("lidar UART: {e}"))?;
        self.send(&Down::Tick(Tick {
            t_us: s.t_us,
            enc: s.enc,
            bumper: s.bumper,
            lidar_bytes: s.lidar.len() as u16,
        }))?;
        self.last = self.recv_step()?;
        Ok(self.last.cmd)
    }

    fn link_noise(&mut self, bytes: &[u8]) -> Result<(), String> {
        self.link
            .write_all(bytes)
            .map_err(|e| format!("sim link: {e}"))
    }

    fn request_home(&mut self) -> Result<(), String> {
        self.send(&Down::Home)
    }
    fn pop_event(&mut self) -> Option<Event> {
        let e = self.events.pop_front();
        if let Some(e) = &e {
            self.frame.note(e);
        }
        e
    }
    fn finished(&self) -> bool {
        self.last.finished
    }
    fn state(&self) -> State {
        self.last.state
    }
    fn pose(&self) -> Pose {
        self.frame.to_world(self.last.pose)
    }
    fn lost(&self) -> bool {
        self.last.lost
    }
    fn counters(&self) -> Counters {
        match &self.report {
            Some(r) => r.counters,
            None => Counters {
                avoidance_events: self.last.avoidance_events,
                ..Counters::new()
            },
        }
    }
    fn loc_stats(&self) -> LocStats {
        self.report.map(|r| r.loc).unwrap_or_default()
    }
    fn parser_stats(&self) -> robovac::robot::lidar::ParserStats {
        self.report.map(|r| r.parser).unwrap_or_default()
    }
    fn end(&mut self) -> Result<(), String> {
        self.send(&Down::End)?;
        loop {
            match self.recv()? {
                Up::Report(r) => {
                    self.report = Some(r);
                    return Ok(());
                }
                Up::Event(e) => self.events.push_back(e),
                _ => {}
            }
        }
    }
}
