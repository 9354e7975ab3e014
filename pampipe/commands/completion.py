"""`pampipe completion bash|zsh`: a shell completion script built from the command-line parser itself.

The script completes the commands, each command's options, the choices of an option that has them
(``--units``, ``--plot-format``, …) and file names elsewhere. zsh reads the bash script through its
``bashcompinit`` layer. Install: ``eval "$(pampipe completion bash)"`` in ``~/.bashrc`` (``zsh`` in
``~/.zshrc``).
"""

from __future__ import annotations

import argparse
import shlex

NAME = "completion"
HELP = "print a shell completion script (bash or zsh); e.g. eval \"$(pampipe completion bash)\" in ~/.bashrc"
SHELLS = ("bash", "zsh")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("shell", choices=SHELLS, help="the shell: bash or zsh")


def run(args: argparse.Namespace) -> int:
    print(script(args.parser, args.shell), end="")
    return 0


def _options(parser: argparse.ArgumentParser) -> tuple[list[str], dict[str, list[str]]]:
    """(every option string, {option: its choices}) of ``parser``."""
    options, choices = [], {}
    for action in parser._actions:
        options += [o for o in action.option_strings if o.startswith("--") or len(action.option_strings) == 1]
        if action.choices and action.option_strings:
            for option in action.option_strings:
                choices[option] = [str(c) for c in action.choices]
    return options, choices


def _words(words) -> str:
    return shlex.quote(" ".join(words))


def script(parser: argparse.ArgumentParser, shell: str) -> str:
    """The completion script of ``parser`` (pampipe's, with its commands in ``parser.commands``) for
    ``shell``."""
    commands = parser.commands
    top, _ = _options(parser)
    cases, values = [], []
    for name, sub in commands.items():
        options, choices = _options(sub)
        positional = [str(c) for a in sub._actions if not a.option_strings and a.choices for c in a.choices]
        cases.append(f"        {name}) options={_words(options)}; positional={_words(positional)} ;;")
        values += [f"        '{name} {option}') COMPREPLY=( $(compgen -W {_words(words)} -- \"$cur\") ); "
                   "return ;;" for option, words in choices.items()]
    body = f"""# {shell} completion for pampipe, written by `pampipe completion {shell}`
_pampipe() {{
    local cur="${{COMP_WORDS[COMP_CWORD]}}" prev="${{COMP_WORDS[COMP_CWORD-1]}}"
    local command="" word options="" positional=""
    for word in "${{COMP_WORDS[@]:1:COMP_CWORD-1}}"; do
        case "$word" in -*) ;; *) command="$word"; break ;; esac
    done
    if [[ -z "$command" ]]; then
        COMPREPLY=( $(compgen -W {_words([*commands, *top])} -- "$cur") )
        return
    fi
    case "$command $prev" in
{chr(10).join(values)}
    esac
    case "$command" in
{chr(10).join(cases)}
    esac
    if [[ "$cur" == -* ]]; then
        COMPREPLY=( $(compgen -W "$options" -- "$cur") )
    elif [[ -n "$positional" ]]; then
        COMPREPLY=( $(compgen -W "$positional" -- "$cur") )
    else
        COMPREPLY=( $(compgen -f -- "$cur") )
    fi
}}
complete -o filenames -o bashdefault -F _pampipe pampipe
"""
    if shell == "zsh":
        return "autoload -U +X bashcompinit && bashcompinit\n" + body
    return body
