//! The `trubal` binary: command-line arguments → a session.

use std::io::IsTerminal;
use std::process::ExitCode;

use trubal::session::{Session, input};

/// `println!`/`eprintln!` panic when the stream is a pipe whose reader has gone
/// (`trubal --help | head -0`); these ignore write errors instead.
macro_rules! say {
    ($($t:tt)*) => {{
        use std::io::Write;
        let _ = writeln!(std::io::stdout(), $($t)*);
    }};
}
macro_rules! complain {
    ($($t:tt)*) => {{
        use std::io::Write;
        let _ = writeln!(std::io::stderr(), $($t)*);
    }};
}

const USAGE: &str = "usage: trubal [FILE | -] [--json] [--keep-going] [--set NAME=VALUE]... [--threads N]
       trubal sweep FILE --out DIR [--grid NAME=V1,V2...] ...   (trubal sweep --help)
       trubal chart FILE.csv --x COL --y COL[,COL...] --out FILE.png ...   (trubal chart --help)
  FILE          run a command file;  -  (or a pipe) reads commands from standard input
  (no FILE)     interactive session on a terminal; TRUBAL.DIR with BATCH: run TRUBAL.DAT into TRUBAL.OUT
  --json        every PRint item is written as one JSON object per line
  --keep-going  report errors in a file and continue with the next line
  --set N=V     replace $N / ${N} in the commands by V
  --threads N   worker threads (default: RAYON_NUM_THREADS or all cores)";

fn main() -> ExitCode {
    let all: Vec<String> = std::env::args().skip(1).collect();
    if all.first().map(String::as_str) == Some("sweep") {
        return trubal::sweep::main(&all[1..]);
    }
    if all.first().map(String::as_str) == Some("chart") {
        return trubal::chart::main(&all[1..]);
    }
    let mut file: Option<String> = None;
    let mut json = false;
    let mut keep_going = false;
    let mut vars = Vec::new();
    let mut threads: Option<usize> = None;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--json" => json = true,
            "--keep-going" | "-k" => keep_going = true,
            "--set" => match args.next().and_then(|kv| {
                kv.split_once('=')
                    .map(|(k, v)| (k.to_string(), v.to_string()))
            }) {
                Some(kv) => vars.push(kv),
                None => {
                    complain!("--set needs NAME=VALUE\n{USAGE}");
                    return ExitCode::from(2);
                }
            },
            "--threads" => match args.next().and_then(|n| n.parse().ok()) {
                Some(n) if n > 0 => threads = Some(n),
                _ => {
                    complain!("--threads needs a positive number\n{USAGE}");
                    return ExitCode::from(2);
                }
            },
            "-h" | "--help" => {
                say!("{USAGE}");
                return ExitCode::SUCCESS;
            }
            "--version" | "-V" => {
                say!("trubal {}", env!("CARGO_PKG_VERSION"));
                return ExitCode::SUCCESS;
            }
            s if s.starts_with("--") => {
                complain!("unknown option {s}\n{USAGE}");
                return ExitCode::from(2);
            }
            s => {
                if file.is_some() {
                    complain!("only one command file may be given\n{USAGE}");
                    return ExitCode::from(2);
                }
                file = Some(s.to_string());
            }
        }
    }
    // The session itself runs on a worker of the pool: with one thread every parallel loop
    // then runs inline, and with more the calling thread takes part instead of sleeping
    // while the others work (each parallel loop from a thread outside the pool is a
    // hand-off and a wake-up, several per step).
    let mut builder = rayon::ThreadPoolBuilder::new().stack_size(16 << 20);
    if let Some(n) = threads {
        builder = builder.num_threads(n);
    }
    match builder.build() {
        Ok(pool) => pool.install(|| session_main(file, json, keep_going, vars)),
        Err(e) => {
            complain!("cannot start the worker threads: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Runs the session the arguments ask for (on a worker thread of the pool).
fn session_main(
    file: Option<String>,
    json: bool,
    keep_going: bool,
    vars: Vec<(String, String)>,
) -> ExitCode {
    let batch = file.is_none() && input::batch_requested();
    let out: Box<dyn std::io::Write + Send> = if batch {
        match std::fs::File::create("TRUBAL.OUT") {
            Ok(f) => Box::new(std::io::BufWriter::new(f)),
            Err(e) => {
                complain!("cannot write TRUBAL.OUT: {e}");
                return ExitCode::FAILURE;
            }
        }
    } else {
        Box::new(std::io::BufWriter::new(std::io::stdout()))
    };
    let mut session = Session::new(out, json);
    session.vars.extend(vars);
    trubal::session::interrupt::install();
    let end = if batch {
        match input::run_file(&mut session, "TRUBAL.DAT", keep_going) {
            Ok(end) => end,
            Err(e) => {
                complain!("{e}");
                return ExitCode::FAILURE;
            }
        }
    } else {
        match file.as_deref() {
            Some("-") => input::run_stdin(&mut session, keep_going),
            Some(f) => match input::run_file(&mut session, f, keep_going) {
                Ok(end) => end,
                Err(e) => {
                    complain!("{e}");
                    return ExitCode::FAILURE;
                }
            },
            None if std::io::stdin().is_terminal() => match input::run_interactive(&mut session) {
                Ok(()) => input::RunEnd::default(),
                Err(e) => {
                    complain!("{e}");
                    return ExitCode::FAILURE;
                }
            },
            None => input::run_stdin(&mut session, keep_going),
        }
    };
    session.flush();
    if end.interrupted {
        // The shell's code for a program stopped by Ctrl-C (128 + SIGINT).
        ExitCode::from(130)
    } else if end.errors > 0 {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}
