//! Settings that persist between runs, as a small RON file in the user's config directory:
//! `$TUMBLE_CONFIG_DIR`, else `$XDG_CONFIG_HOME/tumble`, else `$HOME/.config/tumble`. On the
//! web, the same RON text in the page's `localStorage` under [`STORAGE_KEY`].
//!
//! Loading never fails: a missing file gives the defaults, and an unreadable or malformed one
//! gives the defaults with a warning. Saving never fails the app either: an unwritable
//! directory only prints a warning.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};

/// The file name inside the config directory.
pub const FILE_NAME: &str = "settings.ron";

/// The `localStorage` key of the web build's settings.
pub const STORAGE_KEY: &str = "tumble.settings";

/// What to draw besides the bodies.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct DebugLayers {
    /// Contact points (red: touching, yellow: speculative).
    pub contacts: bool,
    /// Contact normals at each point, and each chain segment's pushing side.
    pub normals: bool,
    /// Each body's fat bounding box.
    pub aabbs: bool,
    /// The broad phase's tree: its inner nodes.
    pub tree: bool,
    /// Contact points coloured by their constraint-graph colour.
    pub graph_colors: bool,
    /// Each body's centre of mass, as small axes.
    pub center_of_mass: bool,
    /// A metre grid behind the bodies.
    pub grid: bool,
    /// Colour dynamic bodies by speed instead of by id.
    pub color_by_speed: bool,
    /// Colour dynamic bodies by their island (over colour by speed).
    pub islands: bool,
    /// Each joint's reaction force at its anchor on body B, and its torque as an arc.
    pub joint_forces: bool,
}

/// Everything the viewer remembers.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Settings {
    /// Worker threads for the step; 0 means all cores.
    pub threads: usize,
    /// The scene last started from the menu.
    pub scene: String,
    /// Whether the side panel is open.
    pub panel_open: bool,
    /// Whether the profile panel is open.
    pub profile_open: bool,
    /// Debug drawing.
    pub debug: DebugLayers,
    /// Wait for the display's refresh (vsync).
    pub vsync: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            threads: 0,
            scene: crate::DEFAULT_SCENE.to_string(),
            panel_open: true,
            profile_open: false,
            debug: DebugLayers {
                grid: true,
                ..DebugLayers::default()
            },
            vsync: true,
        }
    }
}

/// The config directory, if one can be named.
pub fn config_dir() -> Option<PathBuf> {
    let var = |name: &str| std::env::var_os(name).filter(|v| !v.is_empty());
    if let Some(dir) = var("TUMBLE_CONFIG_DIR") {
        return Some(PathBuf::from(dir));
    }
    if let Some(dir) = var("XDG_CONFIG_HOME") {
        return Some(PathBuf::from(dir).join("tumble"));
    }
    var("HOME").map(|home| PathBuf::from(home).join(".config").join("tumble"))
}

impl Settings {
    /// Reads the settings file; the defaults when there is none or it cannot be read.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn load() -> Settings {
        config_dir().map_or_else(Settings::default, |dir| Settings::load_from(&dir))
    }

    /// Reads the settings from the page's `localStorage`; the defaults when there are none
    /// or they cannot be read.
    #[cfg(target_arch = "wasm32")]
    pub fn load() -> Settings {
        let text = web_sys::window()
            .and_then(|w| w.local_storage().ok().flatten())
            .and_then(|storage| storage.get_item(STORAGE_KEY).ok().flatten());
        text.and_then(|t| Settings::parse(&t).ok())
            .unwrap_or_default()
    }

    /// Reads `dir/settings.ron`; the defaults when there is none or it cannot be read.
    pub fn load_from(dir: &std::path::Path) -> Settings {
        let path = dir.join(FILE_NAME);
        match std::fs::read_to_string(&path) {
            Ok(text) => Settings::parse(&text).unwrap_or_else(|e| {
                eprintln!(
                    "warning: {}: {e}; using the default settings",
                    path.display()
                );
                Settings::default()
            }),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Settings::default(),
            Err(e) => {
                eprintln!(
                    "warning: cannot read {}: {e}; using the default settings",
                    path.display()
                );
                Settings::default()
            }
        }
    }

    /// Parses the RON text of a settings file (unknown fields are ignored, missing ones take
    /// their defaults, so files from other versions still load).
    pub fn parse(text: &str) -> Result<Settings, String> {
        ron::from_str(text).map_err(|e| e.to_string())
    }

    /// The RON text of these settings.
    pub fn to_ron(&self) -> String {
        ron::ser::to_string_pretty(self, ron::ser::PrettyConfig::default())
            .unwrap_or_else(|_| String::new())
    }

    /// Writes the settings file; a failure is reported on stderr and otherwise ignored.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn save(&self) {
        if let Some(dir) = config_dir() {
            self.save_to(&dir);
        }
    }

    /// Writes the settings to the page's `localStorage`; a failure (storage disabled or
    /// full) is ignored.
    #[cfg(target_arch = "wasm32")]
    pub fn save(&self) {
        if let Some(storage) = web_sys::window().and_then(|w| w.local_storage().ok().flatten()) {
            let _ = storage.set_item(STORAGE_KEY, &self.to_ron());
        }
    }

    /// Writes `dir/settings.ron` (creating `dir`); a failure is reported on stderr and
    /// otherwise ignored. Returns whether it was written.
    pub fn save_to(&self, dir: &std::path::Path) -> bool {
        let path = dir.join(FILE_NAME);
        let result = std::fs::create_dir_all(dir).and_then(|()| {
            // Write beside, then rename: a crash never leaves half a file.
            let tmp = dir.join(format!("{FILE_NAME}.tmp"));
            std::fs::write(&tmp, self.to_ron())?;
            std::fs::rename(&tmp, &path)
        });
        match result {
            Ok(()) => true,
            Err(e) => {
                eprintln!("warning: cannot save settings to {}: {e}", path.display());
                false
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_tolerant_parse() {
        let mut s = Settings {
            threads: 3,
            scene: "pyramid".into(),
            ..Settings::default()
        };
        s.debug.aabbs = true;
        assert_eq!(Settings::parse(&s.to_ron()).unwrap(), s);
        // Missing fields take defaults.
        let partial = Settings::parse("(threads: 2)").unwrap();
        assert_eq!(partial.threads, 2);
        assert_eq!(partial.scene, crate::DEFAULT_SCENE);
        assert!(Settings::parse("(threads: \"many\")").is_err());
    }

    #[test]
    fn saves_loads_and_never_fails() {
        let dir = std::env::temp_dir().join(format!("tumble-settings-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        // Nothing saved yet: defaults.
        assert_eq!(Settings::load_from(&dir), Settings::default());
        let s = Settings {
            threads: 2,
            profile_open: true,
            ..Settings::default()
        };
        assert!(s.save_to(&dir));
        assert_eq!(Settings::load_from(&dir), s);
        // A malformed file: defaults, no panic.
        std::fs::write(dir.join(FILE_NAME), "(threads: [").unwrap();
        assert_eq!(Settings::load_from(&dir), Settings::default());
        // An unwritable place (a directory under a regular file): false, no panic.
        assert!(!s.save_to(&dir.join(FILE_NAME).join("sub")));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
