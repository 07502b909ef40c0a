//! `calibrate` on several logs: the campaign's options, refused where they cannot apply, and
//! its runs read and joined by the engine (`driftlab::log::campaign::join`). Apart from
//! `calibrate.rs` because it is the one place the command meets runs.

use super::calibrate::Args;
use super::common::CliError;
use driftlab::files::calibration;
use driftlab::models;

impl Args {
    /// Refuses the campaign's options without a campaign, and the options a campaign cannot
    /// take yet.
    pub(super) fn refuse_campaign_options(&self) -> Result<(), CliError> {
        // Before any run is read: a mistyped glob of thousands of logs is refused at once.
        let n = self.log.len();
        if n > driftlab::log::campaign::MAX_RUNS {
            return Err(CliError::Message(
                driftlab::log::campaign::CampaignError::TooManyRuns(n).to_string(),
            ));
        }
        if let Some(t) = self.temp_tolerance {
            models::campaign::check_tolerance("--temp-tolerance", t)
                .map_err(|e| CliError::Message(e.to_string()))?;
        }
        if self.log.len() == 1 {
            if self.per_run_offset {
                return Err(CliError::Message(
                    "--per-run-offset needs two runs or more: a turn-on offset is told apart \
                     from K0 only between runs"
                        .into(),
                ));
            }
            if self.temp_tolerance.is_some() {
                return Err(CliError::Message(
                    "--temp-tolerance is for the plateaus several runs share: give two runs or \
                     more"
                        .into(),
                ));
            }
        } else if !self.plateaus.is_empty() {
            return Err(CliError::Message(
                "--plateau with several runs: each run's plateaus are found on its own time; \
                 give the plateaus of a run by calibrating it alone, or let the detector find \
                 them"
                    .into(),
            ));
        }
        Ok(())
    }

    /// The campaign options, as given.
    pub(super) fn campaign_options(&self) -> models::campaign::CampaignOptions {
        models::campaign::CampaignOptions {
            per_run_offset: self.per_run_offset,
            tolerance_c: self
                .temp_tolerance
                .unwrap_or(models::campaign::DEFAULT_TOLERANCE_C),
        }
    }

    /// Reads every run (only the calibration columns when every axis is Vakhrameev's) and
    /// joins them into one campaign (one run is its log as read) by the engine's one path
    /// ([`models::campaign::JoinedRuns::join`]), which names them and keeps the one file's
    /// SHA-256.
    pub(super) fn read_runs(
        &self,
        columns_only: bool,
    ) -> Result<models::campaign::JoinedRuns, CliError> {
        let mut runs = Vec::with_capacity(self.log.len());
        for path in &self.log {
            let input = self.log_args.open(path)?;
            // The file's hash is taken beside the read.
            let (log, sha256) = std::thread::scope(|scope| {
                let sha =
                    scope.spawn(|| calibration::sha256_input(&input).map_err(|e| e.to_string()));
                let log = if columns_only {
                    self.log_args.read_columns(&input)
                } else {
                    self.log_args.read(&input)
                };
                let sha256 = sha
                    .join()
                    .unwrap_or_else(|_| Err("the hashing thread failed".to_string()));
                (log, sha256)
            });
            runs.push(driftlab::log::campaign::RunInput {
                log: log?,
                sha256: sha256?,
            });
        }
        models::campaign::JoinedRuns::join(runs, &self.log)
            .map_err(|e| CliError::Message(super::log_source::in_flags(&e.to_string())))
    }
}
