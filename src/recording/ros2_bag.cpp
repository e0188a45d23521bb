// ROS 2 bags: SQLite storage (.db3, rosbag2_storage_default_plugins: tables `topics` and `messages`) and MCAP
// storage (mcap_reader.hpp), both holding CDR messages (cdr.hpp).
#include <sqlite3.h>

#include <algorithm>
#include <map>
#include <stdexcept>

#include "backend.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/recording/cdr.hpp"
#include "seqtopo/recording/mcap_reader.hpp"

namespace seqtopo::recording::detail {
namespace {

// Decodes one CDR message of `type` into the image or pose visitor; malformed bytes name file and topic.
void decode_image(MessageType type, std::span<const std::uint8_t> data, bool with_data, const std::string& subject,
                  const std::string& topic, std::int64_t log_time,
                  const std::function<void(RosImage&, std::int64_t)>& visit) {
  RosImage m;
  try {
    if (!with_data) {
      m.stamp = decode_stamp_cdr(data);
      m.compressed = type == MessageType::compressed_image;
    } else if (type == MessageType::image) {
      m = decode_image_cdr(data);
    } else {
      m = decode_compressed_image_cdr(data);
    }
  } catch (const std::invalid_argument& e) {
    throw InputError(subject, "topic " + topic + ": malformed message: " + e.what());
  }
  visit(m, log_time);
}

void decode_pose(MessageType type, std::span<const std::uint8_t> data, const std::string& subject,
                 const std::string& topic, std::int64_t log_time,
                 const std::function<void(const RosPose&, std::int64_t)>& visit) {
  RosPose p;
  try {
    p = type == MessageType::odometry ? decode_odometry_cdr(data) : decode_pose_stamped_cdr(data);
  } catch (const std::invalid_argument& e) {
    throw InputError(subject, "topic " + topic + ": malformed message: " + e.what());
  }
  visit(p, log_time);
}

// ---- SQLite (.db3) --------------------------------------------------------------------------------------

struct Db {
  sqlite3* db = nullptr;
  std::string path;
  explicit Db(std::string p) : path(std::move(p)) {
    if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
      const std::string why = db ? sqlite3_errmsg(db) : "out of memory";
      sqlite3_close(db);
      throw InputError(path, "cannot open as a ROS 2 SQLite bag: " + why);
    }
  }
  ~Db() { sqlite3_close(db); }
  Db(const Db&) = delete;
  Db& operator=(const Db&) = delete;
};

struct Statement {
  sqlite3_stmt* s = nullptr;
  Statement(const Db& db, const char* sql) {
    if (sqlite3_prepare_v2(db.db, sql, -1, &s, nullptr) != SQLITE_OK) {
      throw InputError(db.path, std::string("not a ROS 2 SQLite bag (") + sqlite3_errmsg(db.db) + ")");
    }
  }
  ~Statement() { sqlite3_finalize(s); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  // SQLITE_ROW or SQLITE_DONE; anything else is an error naming the file.
  bool step(const Db& db) {
    const int rc = sqlite3_step(s);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    throw InputError(db.path, std::string("cannot read the bag (") + sqlite3_errmsg(db.db) + ")");
  }
  std::string text(int column) const {
    const auto* t = sqlite3_column_text(s, column);
    return t ? reinterpret_cast<const char*>(t) : "";
  }
};

// Both ROS 2 storages hold CDR messages by topic: the topic list and the decoding are shared, the storage
// only says how to visit one topic's messages in time order.
class CdrBag : public Backend {
 public:
  explicit CdrBag(std::string subject) : subject_(std::move(subject)) {}

  std::vector<Topic> topics() const final {
    std::vector<Topic> out;
    for (const auto& [name, t] : topics_) out.push_back(t);
    return out;
  }

  void read_images(const std::string& topic, bool with_data,
                   const std::function<void(RosImage&, std::int64_t)>& visit) const final {
    const MessageType type = message_type(topics_.at(topic).type);
    each(topic, [&](std::span<const std::uint8_t> data, std::int64_t t) {
      decode_image(type, data, with_data, subject_, topic, t, visit);
    });
  }

  void read_poses(const std::string& topic,
                  const std::function<void(const RosPose&, std::int64_t)>& visit) const final {
    const MessageType type = message_type(topics_.at(topic).type);
    each(topic, [&](std::span<const std::uint8_t> data, std::int64_t t) {
      decode_pose(type, data, subject_, topic, t, visit);
    });
  }

 protected:
  using MessageVisit = std::function<void(std::span<const std::uint8_t>, std::int64_t)>;
  // visit(data, time [ns]) for every message of `topic`, in time order.
  virtual void each(const std::string& topic, const MessageVisit& visit) const = 0;

  std::string subject_;
  std::map<std::string, Topic> topics_;
};

class SqliteBag final : public CdrBag {
 public:
  SqliteBag(const std::vector<std::string>& files, std::string subject) : CdrBag(std::move(subject)) {
    for (const auto& f : files) dbs_.push_back(std::make_unique<Db>(f));
    for (const auto& db : dbs_) {
      Statement q(*db,
                  "SELECT topics.name, topics.type, COUNT(messages.id) FROM topics LEFT JOIN messages ON "
                  "messages.topic_id = topics.id GROUP BY topics.id ORDER BY topics.name");
      while (q.step(*db)) {
        Topic& t = topics_[q.text(0)];
        t.name = q.text(0);
        t.type = q.text(1);
        t.messages += static_cast<std::uint64_t>(sqlite3_column_int64(q.s, 2));
      }
    }
  }

 private:
  void each(const std::string& topic, const MessageVisit& f) const override {
    for (const auto& db : dbs_) {
      Statement q(*db,
                  "SELECT messages.timestamp, messages.data FROM messages JOIN topics ON messages.topic_id = "
                  "topics.id WHERE topics.name = ?1 ORDER BY messages.timestamp, messages.id");
      sqlite3_bind_text(q.s, 1, topic.c_str(), -1, SQLITE_TRANSIENT);
      while (q.step(*db)) {
        const auto* blob = static_cast<const std::uint8_t*>(sqlite3_column_blob(q.s, 1));
        const auto size = static_cast<std::size_t>(sqlite3_column_bytes(q.s, 1));
        f(std::span<const std::uint8_t>(blob, blob ? size : 0), sqlite3_column_int64(q.s, 0));
      }
    }
  }

  std::vector<std::unique_ptr<Db>> dbs_;
};

// ---- MCAP -----------------------------------------------------------------------------------------------

class McapBag final : public CdrBag {
 public:
  McapBag(const std::vector<std::string>& files, std::string subject) : CdrBag(std::move(subject)) {
    for (const auto& f : files) {
      readers_.emplace_back(f);
      const McapReader& r = readers_.back();
      for (const auto& [id, c] : r.channels()) {
        const auto s = r.schemas().find(c.schema_id);
        Topic& t = topics_[c.topic];
        t.name = c.topic;
        if (s != r.schemas().end()) t.type = s->second.name;
        t.messages += r.message_counts().at(id);
        if (MessageType type = message_type(t.type); type != MessageType::other && c.message_encoding != "cdr") {
          throw InputError(f, "topic " + c.topic + ": message encoding '" + c.message_encoding +
                                  "' is not supported (ROS 2 bags hold cdr)");
        }
      }
    }
  }

 private:
  void each(const std::string& topic, const MessageVisit& f) const override {
    for (const auto& r : readers_) {
      std::vector<std::uint16_t> ids;
      for (const auto& [id, c] : r.channels()) {
        if (c.topic == topic) ids.push_back(id);
      }
      if (ids.empty()) continue;
      r.for_each_message(
          [&](const McapChannel&, const McapMessage& m) { f(m.data, static_cast<std::int64_t>(m.log_time)); }, ids);
    }
  }

  std::vector<McapReader> readers_;
};

}  // namespace

std::unique_ptr<Backend> open_ros2_sqlite(const std::vector<std::string>& files, const std::string& subject) {
  return std::make_unique<SqliteBag>(files, subject);
}

std::unique_ptr<Backend> open_ros2_mcap(const std::vector<std::string>& files, const std::string& subject) {
  return std::make_unique<McapBag>(files, subject);
}

}  // namespace seqtopo::recording::detail
