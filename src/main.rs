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
  FILE          run a command file;  -  (or a pipe) reads commands from standard input
  (no FILE)     interactive session on a terminal; TRUBAL.DIR with BATCH: run TRUBAL.DAT into TRUBAL.OUT
  --json        every PRint item is written as one JSON object per line
  --keep-going  report errors in a file and continue with the next line
  --set N=V     replace $N / ${N} in the commands by V
  --threads N   worker threads (default: RAYON_NUM_THREADS or all cores)";

fn main() -> ExitCode {
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
            "--version" => {
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
    if let Some(n) = threads {
        let _ = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global();
    }
    let batch = file.is_none() && input::batch_requested();
    let out: Box<dyn std::io::Write> = if batch {
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
    let errors = if batch {
        match input::run_file(&mut session, "TRUBAL.DAT", keep_going) {
            Ok(n) => n,
            Err(e) => {
                complain!("{e}");
                return ExitCode::FAILURE;
            }
        }
    } else {
        match file.as_deref() {
            Some("-") => input::run_stdin(&mut session, keep_going),
            Some(f) => match input::run_file(&mut session, f, keep_going) {
                Ok(n) => n,
                Err(e) => {
                    complain!("{e}");
                    return ExitCode::FAILURE;
                }
            },
            None if std::io::stdin().is_terminal() => match input::run_interactive(&mut session) {
                Ok(()) => 0,
                Err(e) => {
                    complain!("{e}");
                    return ExitCode::FAILURE;
                }
            },
            None => input::run_stdin(&mut session, keep_going),
        }
    };
    session.flush();
    if errors > 0 {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}
