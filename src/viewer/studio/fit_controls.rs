//! The fit controls: factor dimension, resolution, smoothing and mapping.

use crate::factor::{defaults, Mapping, Settings};

pub(super) struct FitControls {
    /// 1D or 2D factors.
    pub dim: usize,
    pub res: usize,
    /// Smoothing weight λ of every factor.
    pub lambda: f64,
    pub mapping: Mapping,
}

impl Default for FitControls {
    fn default() -> Self {
        FitControls { dim: 1, res: defaults::RES_1D, lambda: defaults::SMOOTH_1D, mapping: Mapping::Auto }
    }
}

/// What a frame of the fit controls changed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct FitChange {
    pub settings: bool,
    pub mapping: bool,
    pub refit: bool,
}

impl FitControls {
    /// The fit settings these controls describe.
    pub fn settings(&self) -> Settings {
        // The command line's rule (`fit --factors --res --lambda`); the sliders keep it valid,
        // and an invalid value falls back to the default smoothing rather than breaking the window.
        crate::pipeline::settings(self.dim, Some(self.res), Some(self.lambda))
            .unwrap_or_else(|_| Settings::uniform(self.dim, self.res))
    }

    /// The controls, and what they changed.
    pub fn ui(&mut self, ui: &mut egui::Ui) -> FitChange {
        let (mut dim, mut res, mut lambda, mut mapping) = (self.dim, self.res, self.lambda, self.mapping);
        ui.horizontal(|ui| {
            ui.label("factors");
            ui.selectable_value(&mut dim, 1, "1D");
            ui.selectable_value(&mut dim, 2, "2D");
        });
        if dim != self.dim {
            res = if dim == 1 { defaults::RES_1D } else { defaults::RES_2D };
            lambda = if dim == 1 { defaults::SMOOTH_1D } else { defaults::SMOOTH_2D };
        }
        let range = if dim == 1 { 8..=512 } else { 8..=64 };
        ui.add(egui::Slider::new(&mut res, range).text("resolution"));
        ui.add(egui::Slider::new(&mut lambda, 1e-8..=1e-1).logarithmic(true).text("λ (smoothing)"));
        ui.horizontal(|ui| {
            ui.label("mapping");
            egui::ComboBox::from_id_salt("mapping").selected_text(mapping.to_string()).show_ui(ui, |ui| {
                for m in [Mapping::Auto, Mapping::Identity, Mapping::Offset(None), Mapping::Inverted(None)] {
                    ui.selectable_value(&mut mapping, m, m.to_string());
                }
            });
        });
        let change = FitChange {
            settings: dim != self.dim || res != self.res || lambda != self.lambda,
            mapping: mapping != self.mapping,
            refit: ui.button("Refit now").clicked(),
        };
        *self = FitControls { dim, res, lambda, mapping };
        ui.small(format!("{} unknowns per channel", self.settings().unknowns()));
        change
    }
}
