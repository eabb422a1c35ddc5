//! `dalembert scenes [--json]`: the scenes as their files describe them.

use crate::protocol::{self, Answer};
use crate::scene::Scene;
use crate::Error;

/// `scenes [--json]`, or `scenes --scene-file PATH [--param k=v] [--json]`: the file's scene
/// as compiled (checked by `Model::new`, its derived basis written out).
pub fn run(file: Option<&str>, params: &[String], as_json: bool) -> Result<String, Error> {
    let answer = match file {
        None => {
            if !params.is_empty() {
                return Err(Error::input("--param goes with --scene-file"));
            }
            Answer::Scenes(
                crate::scene::SCENES
                    .iter()
                    .map(|s| s.description())
                    .collect(),
            )
        }
        Some(path) => {
            let params: Vec<(String, f64)> = params
                .iter()
                .map(|p| protocol::parse_param(p))
                .collect::<Result<_, _>>()?;
            let file = super::read_scene_file(path)?.with_params(&params)?;
            let model = crate::Model::new(&file)?;
            Answer::Scenes(vec![model.scene.description()])
        }
    };
    Ok(answer.render(as_json))
}
