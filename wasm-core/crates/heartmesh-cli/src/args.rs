//! A small hand-written option parser: `--name value`, `--name=value`, `-o value`, switches, and
//! positional arguments; `--` ends the options. Kept tiny on purpose: the CLI has few commands.

use crate::error::CliError;

/// The parsed command line of one subcommand.
#[derive(Debug, Default)]
pub struct Parsed {
    pub positional: Vec<String>,
    /// (canonical name without dashes, value), in command-line order.
    pub values: Vec<(String, String)>,
    pub switches: Vec<String>,
}

impl Parsed {
    /// The value of option `name` (canonical name).
    pub fn value(&self, name: &str) -> Option<&str> {
        self.values
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }

    /// Every value of option `name`, in command-line order (for [`REPEATABLE`] options).
    pub fn values_of<'a>(&'a self, name: &'a str) -> impl Iterator<Item = &'a str> + 'a {
        self.values
            .iter()
            .filter(move |(n, _)| n == name)
            .map(|(_, v)| v.as_str())
    }

    pub fn switch(&self, name: &str) -> bool {
        self.switches.iter().any(|s| s == name)
    }

    /// The value of option `name` as a finite number, if given; a usage error names the option.
    pub fn number(&self, name: &str) -> Result<Option<f64>, CliError> {
        self.value(name)
            .map(|v| {
                v.trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| CliError::usage(format!("--{name}: {v:?} is not a number")))
            })
            .transpose()
    }

    /// The value of option `name` as a whole number, if given; a usage error names the option.
    pub fn whole(&self, name: &str) -> Result<Option<u64>, CliError> {
        self.value(name)
            .map(|v| {
                v.trim()
                    .parse::<u64>()
                    .map_err(|_| CliError::usage(format!("--{name}: {v:?} is not a whole number")))
            })
            .transpose()
    }
}

/// Options with a value that may be given more than once, each value kept in order (a list, as
/// `--leave-out A --leave-out B`); any other given twice is a usage error.
const REPEATABLE: &[&str] = &["leave-out"];

/// Options of a command: names that take a value and switches; `aliases` maps short forms
/// (e.g. `-o`) to canonical names.
pub struct Spec<'a> {
    pub with_value: &'a [&'a str],
    pub switches: &'a [&'a str],
    pub aliases: &'a [(&'a str, &'a str)],
}

pub fn parse(args: &[String], spec: &Spec) -> Result<Parsed, CliError> {
    let mut out = Parsed::default();
    let mut it = args.iter();
    let mut only_positional = false;
    while let Some(arg) = it.next() {
        if only_positional || !arg.starts_with('-') || arg == "-" {
            out.positional.push(arg.clone());
            continue;
        }
        if arg == "--" {
            only_positional = true;
            continue;
        }
        let (raw, inline) = match arg.split_once('=') {
            Some((n, v)) => (n, Some(v.to_string())),
            None => (arg.as_str(), None),
        };
        let name = spec
            .aliases
            .iter()
            .find(|(a, _)| *a == raw)
            .map(|(_, c)| c.to_string())
            .or_else(|| raw.strip_prefix("--").map(str::to_string))
            .ok_or_else(|| CliError::usage(format!("unknown option {raw}")))?;
        if spec.switches.contains(&name.as_str()) {
            if inline.is_some() {
                return Err(CliError::usage(format!("--{name} takes no value")));
            }
            out.switches.push(name);
        } else if spec.with_value.contains(&name.as_str()) {
            if out.value(&name).is_some() && !REPEATABLE.contains(&name.as_str()) {
                return Err(CliError::usage(format!("--{name} given twice")));
            }
            let v = match inline {
                Some(v) => v,
                None => it
                    .next()
                    .cloned()
                    .ok_or_else(|| CliError::usage(format!("--{name} needs a value")))?,
            };
            out.values.push((name, v));
        } else {
            return Err(CliError::usage(format!("unknown option {raw}")));
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SPEC: Spec = Spec {
        with_value: &["output", "lambda", "surface"],
        switches: &["quiet"],
        aliases: &[("-o", "output")],
    };

    fn v(s: &[&str]) -> Vec<String> {
        s.iter().map(|x| x.to_string()).collect()
    }

    #[test]
    fn forms() {
        let p = parse(
            &v(&[
                "in.csv",
                "-o",
                "m.obj",
                "--lambda=-3",
                "--quiet",
                "--",
                "--x",
            ]),
            &SPEC,
        )
        .unwrap();
        assert_eq!(p.positional, v(&["in.csv", "--x"]));
        assert_eq!(p.value("output"), Some("m.obj"));
        assert_eq!(p.value("lambda"), Some("-3"));
        assert!(p.switch("quiet"));
    }

    #[test]
    fn errors() {
        let msg = |a: &[&str]| parse(&v(a), &SPEC).unwrap_err().message();
        assert!(msg(&["--nope"]).contains("unknown option --nope"));
        assert!(msg(&["-o"]).contains("--output needs a value"));
        assert!(msg(&["-o", "a", "--output", "b"]).contains("twice"));
        assert!(msg(&["--quiet=1"]).contains("takes no value"));
    }
}
